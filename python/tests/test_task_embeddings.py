"""data/task_descriptions/metaworld_embeddings.json: CARE's task-metadata embeddings.

Reads the committed JSON only (the embedding package, wordllama, is not needed here):
one entry per Meta-World task, named and ordered as the C++ registry's MT50, each a finite
unit vector of the stated dimension, and close for related tasks, far for unrelated ones.
scripts/embed_task_descriptions.py makes the file; its --help and one-line errors are
checked too (neither loads the model).
"""

import json
import math
import subprocess
import sys

import pytest

from conftest import REPO

DATA = REPO / "data" / "task_descriptions"
JSON_PATH = DATA / "metaworld_embeddings.json"
SCRIPT = REPO / "scripts" / "embed_task_descriptions.py"


@pytest.fixture(scope="module")
def doc():
    with open(JSON_PATH, encoding="utf-8") as f:
        return json.load(f)


def cosine(doc, a, b):
    u, v = doc["tasks"][a]["embedding"], doc["tasks"][b]["embedding"]
    return sum(x * y for x, y in zip(u, v)) / math.sqrt(sum(x * x for x in u) * sum(y * y for y in v))


def test_header_names_the_model(doc):
    assert doc["package"] == "wordllama"
    assert doc["package_version"]
    assert doc["model"] == "l2_supercat"
    assert doc["dim"] == 256
    assert len(doc["date"]) == 10


def test_fifty_tasks_in_the_registry_order(doc):
    assert len(doc["tasks"]) == 50
    manyworlds = pytest.importorskip("manyworlds")
    mt50 = manyworlds.benchmarks.MT50_TASKS
    if not mt50:
        pytest.skip("this build of manyworlds has no MuJoCo suites")
    # the same names in the same order: a task's position is its MT50 one-hot index
    assert list(doc["tasks"]) == list(mt50)


def test_vectors_are_finite_unit_vectors_of_the_stated_dimension(doc):
    for name, entry in doc["tasks"].items():
        assert entry["description"].strip(), name
        vec = entry["embedding"]
        assert len(vec) == doc["dim"], name
        assert all(isinstance(x, float) and math.isfinite(x) for x in vec), name
        # rounded to 6 decimals: the norm is 1 to within 256 * 5e-7
        assert math.sqrt(sum(x * x for x in vec)) == pytest.approx(1.0, abs=1e-4), name


def test_related_tasks_are_closer_than_unrelated_ones(doc):
    # measured 2026-11-28: 0.836 against 0.048, 0.702 against 0.044, 0.962 against 0.081
    assert cosine(doc, "drawer-open", "drawer-close") > cosine(doc, "drawer-open", "basketball") + 0.3
    assert cosine(doc, "door-open", "door-close") > cosine(doc, "door-open", "soccer") + 0.3
    assert cosine(doc, "window-open", "window-close") > cosine(doc, "window-open", "hammer") + 0.3
    # no two tasks share an embedding
    names = list(doc["tasks"])
    assert all(cosine(doc, a, b) < 0.99 for i, a in enumerate(names) for b in names[i + 1:])


def test_descriptions_match_the_yaml(doc):
    yaml = pytest.importorskip("yaml")
    with open(DATA / "metaworld.yaml", encoding="utf-8") as f:
        tasks = yaml.safe_load(f)["tasks"]
    assert {n: " ".join(t.split()) for n, t in tasks.items()} == \
        {n: e["description"] for n, e in doc["tasks"].items()}


def run_script(*args):
    return subprocess.run([sys.executable, str(SCRIPT), *args], capture_output=True, text=True, timeout=60)


def test_script_help_and_one_line_errors(tmp_path):
    assert run_script("--help").returncode == 0
    bad = run_script("--date", "yesterday", "--output", str(tmp_path / "out.json"))
    assert bad.returncode == 2 and bad.stderr.count("\n") == 1 and "--date" in bad.stderr
    assert not (tmp_path / "out.json").exists()
