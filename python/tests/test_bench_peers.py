"""The PyTorch peers that `bench agent` is measured against build the networks manyworlds builds:
for every SAC architecture, the parameter counts of the peer's networks
(bench/peers/sac_update.py --check) equal those of the C++ learner (`bench agent --json`), actor,
twin critics and task encoders alike. A speed ratio against a smaller or larger network would
mean nothing."""

import json
import subprocess

import pytest

from conftest import REPO, cli_path

# The peer runs on Debian's python3-torch, as the benchmarks do (docs/benchmarks.md).
PEER_PYTHON = "/usr/bin/python3"
ARCHITECTURES = ("mlp", "multihead", "task_encoder", "moe", "soft_modular", "paco", "moore")


def _peer_has_torch():
    try:
        return subprocess.run([PEER_PYTHON, "-c", "import torch"], capture_output=True,
                              timeout=120).returncode == 0
    except (OSError, subprocess.TimeoutExpired):
        return False


pytestmark = [
    pytest.mark.skipif(cli_path() is None, reason="the manyworlds program is not built"),
    pytest.mark.skipif(not _peer_has_torch(), reason=f"{PEER_PYTHON} has no torch"),
]


def _json(command):
    done = subprocess.run(command, capture_output=True, text=True, timeout=300,
                          env={"OPENBLAS_NUM_THREADS": "1", "PATH": "/usr/bin:/bin"})
    assert done.returncode == 0, done.stderr
    return json.loads(done.stdout)


@pytest.mark.parametrize("architecture", ARCHITECTURES)
def test_the_peer_builds_the_networks_of_the_learner(architecture):
    ours = _json([cli_path(), "bench", "agent", "--architecture", architecture, "--tasks", "10",
                  "--batch", "4", "--updates", "1", "--repeats", "1", "--disentangled-alpha",
                  "--json"])["params"]
    peer = _json([PEER_PYTHON, str(REPO / "bench" / "peers" / "sac_update.py"),
                  "--architecture", architecture, "--tasks", "10", "--check"])["params"]
    assert peer["actor"]["pytorch"] == ours["actor"]
    assert peer["twin_critics"]["pytorch"] == ours["critics"]
    assert peer.get("task encoder", {}).get("pytorch", 0) == ours["task_encoder"]
    assert peer.get("mixture encoder", {}).get("pytorch", 0) == ours["mixture_encoder"]
