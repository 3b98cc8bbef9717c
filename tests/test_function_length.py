"""No function of the package is over 60 lines (its own lines: nested functions and classes are measured on
their own) unless it is a numba kernel, or a ``# long: <why>`` comment on the line above it (above its
decorators) says why, or it is in :data:`ALLOWED`, the list of functions still to be shortened (each entry
fails this test once the function is short, so the list only shrinks)."""

from __future__ import annotations

import ast
from pathlib import Path

import spcotmhp

ROOT = Path(spcotmhp.__file__).parent
LIMIT = 60

ALLOWED: set[str] = set()  # functions still to be shortened (empty: every long function says why)


def own_lines(node: ast.FunctionDef | ast.AsyncFunctionDef) -> int:
    """Lines from the def to the end, without the lines of nested functions and classes."""
    lines = set(range(node.lineno, node.end_lineno + 1))
    for sub in ast.walk(node):
        if sub is not node and isinstance(sub, (ast.FunctionDef, ast.AsyncFunctionDef, ast.ClassDef)):
            lines -= set(range(sub.lineno - len(sub.decorator_list), sub.end_lineno + 1))
    return len(lines)


def long_functions() -> dict[str, int]:
    """Every function over LIMIT lines that is not a numba kernel and has no ``# long:`` comment: {name: lines}."""
    out = {}
    for path in sorted(ROOT.rglob("*.py")):
        source = path.read_text(encoding="utf-8").splitlines()
        tree = ast.parse("\n".join(source))
        parents = {child: parent for parent in ast.walk(tree) for child in ast.iter_child_nodes(parent)}
        for node in ast.walk(tree):
            if not isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) or own_lines(node) <= LIMIT:
                continue
            if any("jit" in ast.unparse(d) for d in node.decorator_list):
                continue
            first = node.decorator_list[0].lineno if node.decorator_list else node.lineno
            if first >= 2 and source[first - 2].strip().startswith("# long:"):
                continue
            names, up = [node.name], parents.get(node)
            while up is not None and not isinstance(up, ast.Module):
                if isinstance(up, (ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
                    names.append(up.name)
                up = parents.get(up)
            out[f"{path.relative_to(ROOT).as_posix()}::{'.'.join(reversed(names))}"] = own_lines(node)
    return out


def test_no_long_function_without_a_reason():
    found = long_functions()
    unexplained = {name: n for name, n in found.items() if name not in ALLOWED}
    assert not unexplained, f"over {LIMIT} lines, with no '# long: <why>' comment above: {unexplained}"


def test_the_allowed_list_only_holds_long_functions():
    shortened = ALLOWED - set(long_functions())
    assert not shortened, f"now {LIMIT} lines or shorter (or gone): remove from ALLOWED: {sorted(shortened)}"
