"""Scenarios: registry, determinism, the robots actually do what the course tasks describe."""

from __future__ import annotations

import math

import pytest

from sims.recording import Recorder
from sims.scenarios import drive, get_scenario, list_scenarios, run_scenario
from sims.scenarios.cart_keyboard import apply_key
from sims.world import World

SHORT_2W1A = {"runs": 1, "moves": 3}


def test_registry_lists_the_course_scenarios():
    names = [s.name for s in list_scenarios()]
    assert names == sorted(names)
    assert {"2w1a-random", "cart-reverse", "cart-keyboard", "cart-avoid"} <= set(names)
    for s in list_scenarios():
        assert s.description and s.scene in ("2w1a", "cart") and s.source_path.endswith(".py")
        assert s.duration_for(s.params) > 0
    with pytest.raises(KeyError):
        get_scenario("no-such-scenario")
    with pytest.raises(ValueError, match="no param"):
        get_scenario("cart-reverse").resolve_params({"sped": 1})


def test_2w1a_random_moves_the_body_and_is_deterministic():
    a = run_scenario("2w1a-random", seed=5, params=SHORT_2W1A)
    b = run_scenario("2w1a-random", seed=5, params=SHORT_2W1A)
    c = run_scenario("2w1a-random", seed=6, params=SHORT_2W1A)
    assert len(a.rows) == 15 * 20
    assert a.to_csv() == b.to_csv() and a.events == b.events
    assert a.to_csv() != c.to_csv()
    xs, ys = a.column("x"), a.column("y")
    moved = max(math.hypot(x - xs[0], y - ys[0]) for x, y in zip(xs, ys, strict=True))
    assert moved > 0.02  # some centimetres
    reached = [e for e in a.events if "reached_deg" in e]
    targets = [e["targets_deg"] for e in a.events if "targets_deg" in e]
    assert len(reached) == len(targets) == 3


def test_2w1a_random_resets_between_runs():
    rec = run_scenario("2w1a-random", params={"runs": 2, "moves": 1, "move_seconds": 2.0})
    # Row 40 (t = 2 s) ends run 1; the reset follows, so run 2's first sample is row 41.
    assert rec.breaks == [41]
    assert rec.column("t")[41] == pytest.approx(2.05)
    assert rec.rows[41][1:4] == pytest.approx([-0.0201, 0.0, 0.070], abs=0.01)  # back at start
    assert any(e["text"] == "world reset" for e in rec.events)


def test_cart_reverse_backs_up_straight():
    rec = run_scenario("cart-reverse")
    x, y = rec.column("x"), rec.column("y")
    assert x[-1] == pytest.approx(-0.28, rel=0.1)
    assert max(abs(v) for v in y) < 0.005
    assert rec.column("left_m_rad_s")[-1] == pytest.approx(-1.0, abs=0.02)


def test_keyboard_rules():
    assert apply_key("up", 0.0, 0.0) == (0.5, 0.5)
    assert apply_key("up", 2.0, 2.0) == (2.0, 2.0)
    assert apply_key("down", -2.0, -1.5) == (-2.0, -2.0)
    assert apply_key("left", 1.0, 1.0) == (0.5, 1.5)
    assert apply_key("right", 1.0, 1.0) == (1.5, 0.5)
    assert apply_key("space", 1.5, -2.0) == (0.0, 0.0)


def test_cart_keyboard_follows_the_key_session():
    rec = run_scenario("cart-keyboard")
    speeds = dict(zip(rec.column("t"), rec.column("right_m_rad_s"), strict=True))
    assert speeds[5.0] == pytest.approx(2.0, abs=0.05)  # four "up" presses, capped at 2
    assert speeds[23.5] == pytest.approx(-1.0, abs=0.05)  # two "down" after the stop
    assert max(rec.column("x")) > 0.4


@pytest.mark.parametrize("seed", [None, 1, 2])
def test_cart_avoid_never_touches_an_obstacle(seed):
    scenario = get_scenario("cart-avoid")
    params = scenario.resolve_params({})
    with World("cart", seed=scenario.seed if seed is None else seed) as world:
        touches: list = []
        world.add_step_hook(lambda w: touches.extend(w.obstacle_contacts()))
        recorder = Recorder(
            world,
            fps=20,
            frames=round(params["seconds"] * 20),
            joints=scenario.joints,
            quantity="speed",
            extra_columns=scenario.extra_columns,
        )
        rec = drive(world, recorder, lambda w, r: scenario.run(w, params, r))
    assert touches == []
    xs, ys = rec.column("x"), rec.column("y")
    travelled = sum(math.dist((xs[i], ys[i]), (xs[i + 1], ys[i + 1])) for i in range(len(xs) - 1))
    assert travelled > 2.0  # it really roams
    assert any("turning" in e["text"] for e in rec.events)  # and really avoids


def test_recording_formats_are_deterministic_and_rounded():
    rec = run_scenario("cart-reverse", params={"seconds": 1.0})
    csv = rec.to_csv()
    assert csv.splitlines()[0].startswith("t,x,y,z,alpha_deg,beta_deg,gamma_deg,heading_deg")
    assert "-0.0000" not in csv and "e-" not in csv
    assert csv.splitlines()[1].startswith("0.000,0.0000,0.0000,")
    assert rec.to_json(scenario="x") == run_scenario(
        "cart-reverse", params={"seconds": 1.0}
    ).to_json(scenario="x")
