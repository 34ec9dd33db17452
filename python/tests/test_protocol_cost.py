"""bench/protocol_cost.py: the projection of a published protocol's cost from a short run."""

import importlib.util
import json
import subprocess
import sys

import pytest

from conftest import REPO, cli_path

SCRIPT = REPO / "bench" / "protocol_cost.py"
spec = importlib.util.spec_from_file_location("protocol_cost", SCRIPT)
protocol_cost = importlib.util.module_from_spec(spec)
spec.loader.exec_module(protocol_cost)


def _row(step, wall_s, updates, time_update_s=0.0):
    return {"step": step, "wall_s": wall_s, "updates": updates, "time_update_s": time_update_s}


def test_rates_and_projection_on_known_rows():
    # Warm-up: 500 steps in 5 s. Then two rounds of 500 updates: 20 s and 30 s, 40 s learning.
    metrics = [_row(500, 5.0, 0), _row(1000, 25.0, 500, 16.0), _row(1500, 55.0, 1000, 24.0)]
    rates = protocol_cost.measure_rates(metrics, {"wall_s": 12.0}, eval_episodes=3, warmup_steps=500)
    assert rates["warmup_step_s"] == pytest.approx(0.01)
    assert rates["loop_step_s"] == pytest.approx(50.0 / 1000)
    assert rates["updates_per_s"] == pytest.approx(1000 / 50.0)
    assert rates["learner_share"] == pytest.approx(40.0 / 50.0)
    assert rates["eval_s_per_episode"] == pytest.approx(4.0)
    parts = protocol_cost.project(rates, steps_per_task=10000, warmup_steps=1500, eval_every=2500,
                                  eval_episodes=50)
    assert parts["warmup_s"] == pytest.approx(15.0)
    assert parts["training_s"] == pytest.approx(8500 * 0.05)
    assert parts["evaluations"] == 4
    assert parts["evaluation_s"] == pytest.approx(4 * 50 * 4.0)
    assert parts["total_s"] == pytest.approx(15.0 + 425.0 + 800.0)


def test_rounds_that_start_in_warm_up_are_not_update_rounds():
    metrics = [_row(400, 4.0, 0), _row(800, 10.0, 300, 5.0)]
    with pytest.raises(ValueError, match="warm-up's end"):
        protocol_cost.measure_rates(metrics, {"wall_s": 1.0}, 1, warmup_steps=500)
    with pytest.raises(ValueError, match="raise --rounds"):
        protocol_cost.measure_rates([_row(500, 5.0, 0)], {"wall_s": 1.0}, 1, warmup_steps=500)


@pytest.mark.skipif(cli_path() is None, reason="the manyworlds program is not built")
def test_a_config_measured_end_to_end(tmp_path):
    # the shipped three-goal MT-SAC config: 100-step episodes, 5,000 steps per task, warm-up 500,
    # an evaluation of 10 episodes every 1,000 steps
    config = REPO / "configs" / "point_nav3_mtsac.yaml"
    out = tmp_path / "cost.json"
    done = subprocess.run([sys.executable, str(SCRIPT), "--config", str(config), "--round-steps", "100",
                           "--rounds", "2", "--eval-episodes", "2", "--threads", "1",
                           "--cli", str(cli_path()), "--json", str(out)],
                          capture_output=True, text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    assert "| CONFIG, 0.005M steps/task |" in done.stdout
    (result,) = json.loads(out.read_text())
    rates, parts = result["rates"], result["projection"]
    # One update per loop step: the loop step costs at least an update.
    assert 0 < rates["learner_share"] < 1
    assert rates["updates_per_s"] * rates["loop_step_s"] == pytest.approx(1.0, rel=1e-6)
    assert parts["evaluations"] == 5 and result["eval_episodes"] == 10
    assert parts["total_s"] == pytest.approx(parts["warmup_s"] + parts["training_s"] + parts["evaluation_s"])
    assert parts["training_s"] == pytest.approx((5000 - 500) * rates["loop_step_s"])


def test_bad_arguments_are_one_line_errors(tmp_path):
    done = subprocess.run([sys.executable, str(SCRIPT), "--rounds", "0"], capture_output=True, text=True)
    assert done.returncode == 2 and "--rounds" in done.stderr.strip().splitlines()[-1]
    done = subprocess.run([sys.executable, str(SCRIPT), "--config", str(tmp_path / "none.yaml"),
                           "--cli", sys.executable], capture_output=True, text=True)
    assert done.returncode == 2 and "no such file" in done.stderr.strip().splitlines()[-1]
