"""Records dm_control's `tolerance` (dm_control.utils.rewards) on a grid of shapes and points,
for tests/dmc/tolerance_test.cc to compare ours with (the official function as the oracle).

    python3 -m venv .venv-dmc && .venv-dmc/bin/pip install dm-control
    .venv-dmc/bin/python scripts/record_dmc_tolerance.py > tests/dmc/data/tolerance_dm_control.json
"""

import json
import math
from importlib.metadata import version

import numpy as np
from dm_control.utils import rewards

SIGMOIDS = ["gaussian", "hyperbolic", "long_tail", "reciprocal", "cosine", "linear",
            "quadratic", "tanh_squared"]
# (lower, upper, margin): a band, a one-sided bound as the tasks use, a point target, margin 0
SHAPES = [(-1.0, 2.0, 0.5), (1.2, math.inf, 0.6), (-math.inf, -15.0, 3.0), (0.0, 0.0, 1.0),
          (0.3, 0.7, 0.0)]
VALUES_AT_MARGIN = [0.0, 0.1, 0.5, 0.9]
POINTS = [float(x) for x in np.linspace(-25.0, 25.0, 41)] + [-15.0, 1.2, 1.8, 2.5, -1.5, 0.35]


def main():
    cases = []
    for sigmoid in SIGMOIDS:
        for lower, upper, margin in SHAPES:
            for value_at_margin in VALUES_AT_MARGIN:
                try:
                    values = [float(rewards.tolerance(x, bounds=(lower, upper), margin=margin,
                                                      sigmoid=sigmoid,
                                                      value_at_margin=value_at_margin))
                              for x in POINTS]
                except ValueError:
                    continue  # a value_at_margin the sigmoid refuses (ours refuses it too)
                cases.append({"sigmoid": sigmoid, "lower": lower, "upper": upper,
                              "margin": margin, "value_at_margin": value_at_margin,
                              "value": values})
    # JSON has no infinity: bounds are written as strings
    for case in cases:
        for key in ("lower", "upper"):
            if math.isinf(case[key]):
                case[key] = "inf" if case[key] > 0 else "-inf"
    print(json.dumps({"dm_control": version("dm-control"), "x": POINTS, "cases": cases}))


if __name__ == "__main__":
    main()
