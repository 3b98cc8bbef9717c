// Renders /openapi.json as a list of operations (method, path, summary, parameters, request and answer schemas).
"use strict";

function el(tag, text, cls) {
  const node = document.createElement(tag);
  if (text !== undefined) node.textContent = text;
  if (cls) node.className = cls;
  return node;
}

function resolve(spec, schema) {
  if (schema && schema.$ref) {
    const name = schema.$ref.split("/").pop();
    return { name, schema: spec.components.schemas[name] };
  }
  return { name: null, schema };
}

function schemaBlock(spec, title, schema) {
  const box = el("div");
  const { name, schema: body } = resolve(spec, schema);
  box.appendChild(el("strong", title + (name ? ` (${name})` : "")));
  box.appendChild(el("pre", JSON.stringify(body, null, 1)));
  return box;
}

function render(spec) {
  const root = document.getElementById("ops");
  root.textContent = "";
  root.appendChild(el("p", `${spec.info.title} ${spec.info.version}: ${spec.info.description || ""}`));
  for (const [path, item] of Object.entries(spec.paths)) {
    for (const [method, op] of Object.entries(item)) {
      const box = el("section", undefined, "op");
      const head = el("h3");
      head.appendChild(el("span", method.toUpperCase(), "method"));
      head.appendChild(el("code", " " + path));
      box.appendChild(head);
      if (op.summary) box.appendChild(el("p", op.summary));
      if (op.description) box.appendChild(el("p", op.description));
      for (const p of op.parameters || []) {
        box.appendChild(el("p", `parameter ${p.name} (${p.in}${p.required ? ", required" : ""}): ` +
                                `${(p.schema && p.schema.description) || p.description || ""}`));
      }
      const content = op.requestBody && op.requestBody.content;
      if (content) {
        for (const [type, media] of Object.entries(content)) {
          box.appendChild(schemaBlock(spec, `request body ${type}`, media.schema));
        }
      }
      for (const [code, answer] of Object.entries(op.responses || {})) {
        const json = answer.content && answer.content["application/json"];
        if (json && json.schema) box.appendChild(schemaBlock(spec, `answer ${code}`, json.schema));
        else box.appendChild(el("p", `answer ${code}: ${answer.description || ""}`));
      }
      root.appendChild(box);
    }
  }
}

fetch("/openapi.json")
  .then((r) => r.json())
  .then(render)
  .catch((e) => { document.getElementById("ops").textContent = "cannot load /openapi.json: " + e; });
