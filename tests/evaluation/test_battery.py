"""The battery reports WN-SPL with the paper's N and with N via the waypoint."""

from __future__ import annotations

from spcotmhp.evaluation.battery import markdown, run_battery, summary


def test_battery_reports_both_readings_of_n():
    results = run_battery([42], params=("supervised",), max_advanced=20)
    home = results[0]
    # battery-42: on several tasks the bedroom nearest from the start is not the one nearest via the waypoint,
    # which the planner reaches (README, "Plans you can trust")
    assert 0.0 <= home.wn_spl < home.wn_spl_via <= 1.0
    s = summary(results)["supervised"]
    assert s["wn_spl_via_min"] == home.wn_spl_via
    table = markdown(results).splitlines()
    assert "advanced WN-SPL via mean (min)" in table[0]
    assert len({row.count("|") for row in table}) == 1
