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
    text = markdown(results).splitlines()
    assert text[0].startswith("Success: the path's last pose within the robot's inscribed radius (0.22 m)")
    table = text[2:]  # the success rule, a blank line, then the table
    assert "advanced WN-SPL via mean (min)" in table[0] and "| set apart |" in table[0]
    assert len({row.count("|") for row in table}) == 1
    assert 0.0 < home.strict_wn_spl_via <= 1.0 and home.set_apart == 0


def test_furnished_battery_plans_every_place_within_reach():
    """battery-0 with furniture: a seating group holds the living room's and a bedroom's mean (their own territories
    are pockets); the planner reaches them from the rest of the home. Before planning per free region, 12 of these
    120 checks and 10 of the tasks were refused ("no free cell the robot fits in: bedroom, living")."""
    home = run_battery([0], params=("supervised",), max_advanced=5, furniture=True)[0]
    assert home.home == "battery-0-furniture"
    assert home.reach_checks > 50 and home.cut_off == 0, home.errors
    assert home.refused == 0 and home.unsafe == 0
    assert "places refused within reach (2 sigma)" in markdown([home]).splitlines()[2]  # under the success rule
