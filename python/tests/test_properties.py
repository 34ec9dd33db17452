"""Property-based checks of the Python package's inputs (hypothesis): actions, make options
and task states drawn from wide strategies (non-finite and huge numbers, wrong shapes and types,
nested values, arbitrary text) either work or raise one of the package's errors with a one-line
message; nothing crashes, and what is accepted steps with finite observations and rewards.

The C++ side has its table-driven probes (tests/envs/option_probe_test.cc,
tests/experiments/config_probe_test.cc) and fuzz targets; this is the same promise kept across
the binding layer, where Python's types (big ints, numpy arrays, dicts) meet C++'s.
"""

import math

import numpy as np
import pytest

hypothesis = pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402
from hypothesis.extra import numpy as hnp  # noqa: E402

import manyworlds  # noqa: E402

# one classic env of each action kind, a MuJoCo manipulation task and the box world
ENV_IDS = ["cartpole", "point-nav", "bandit", "reach", "box-world-simple"]
ERRORS = (ValueError, TypeError, manyworlds.Error)
SETTINGS = settings(max_examples=150, deadline=None, derandomize=True, database=None,
                    suppress_health_check=[HealthCheck.too_slow])


def one_line(error: BaseException) -> None:
    text = str(error)
    assert text, f"{type(error).__name__} without a message"
    assert "\n" not in text, f"a multi-line error: {text[:300]!r}"
    assert len(text) < 2000, f"an error of {len(text)} characters: {text[:200]!r}"


def all_finite(*arrays) -> bool:
    """Whether every number in the arrays (or in the values of dict observations) is finite."""
    flat = []
    for a in arrays:
        flat.extend(a.values() if isinstance(a, dict) else [a])
    return all(np.all(np.isfinite(np.asarray(a, dtype=np.float64))) for a in flat)


numbers = st.one_of(
    st.integers(min_value=-(2**70), max_value=2**70),
    st.floats(allow_nan=True, allow_infinity=True),
)
scalars = st.one_of(numbers, st.booleans(), st.none(), st.text(max_size=40))
values = st.recursive(scalars, lambda inner: st.one_of(st.lists(inner, max_size=4),
                                                       st.dictionaries(st.text(max_size=8), inner,
                                                                       max_size=4)),
                      max_leaves=12)


def available_ids():
    known = set(manyworlds.env_ids())
    return [env_id for env_id in ENV_IDS if env_id in known]


@pytest.fixture(scope="module")
def envs():
    made = {env_id: manyworlds.make(env_id) for env_id in available_ids()}
    yield made
    for env in made.values():
        env.close()


@SETTINGS
@given(data=st.data())
def test_any_action_steps_or_is_refused_in_one_line(envs, data):
    env_id = data.draw(st.sampled_from(sorted(envs)))
    env = envs[env_id]
    env.reset(seed=data.draw(st.integers(0, 2**32 - 1)))
    shape = data.draw(st.one_of(
        st.just(env.action_space.shape),
        st.lists(st.integers(0, 3), max_size=3).map(tuple),
    ))
    elements = st.floats(allow_nan=True, allow_infinity=True, width=64)
    action = data.draw(st.one_of(
        st.integers(-10, 10),
        st.lists(elements, max_size=8),
        hnp.arrays(np.float64, shape, elements=elements),
        hnp.arrays(np.float32, shape, elements=st.floats(width=32, allow_nan=True)),
        st.text(max_size=5),
        st.none(),
    ))
    try:
        obs, reward, terminated, truncated, info = env.step(action)
    except ERRORS as error:
        one_line(error)
        env.reset()  # the env stays usable after a refused action
        return
    assert all_finite(obs, [reward])
    if terminated or truncated:
        env.reset()


@SETTINGS
@given(data=st.data())
def test_any_make_option_makes_a_working_env_or_is_refused_in_one_line(data):
    entries = {entry["id"]: entry for entry in manyworlds.registry()}
    env_id = data.draw(st.sampled_from(available_ids()))
    names = [option["name"] for option in entries[env_id]["options"]]
    name = data.draw(st.one_of(st.sampled_from(names), st.text(min_size=1, max_size=12)))
    value = data.draw(values)
    try:
        env = manyworlds.make(env_id, **{name: value})
    except ERRORS as error:
        one_line(error)
        return
    try:
        obs, _ = env.reset(seed=1)
        assert all_finite(obs)
        for _ in range(5):
            obs, reward, terminated, truncated, _ = env.step(env.action_space.sample())
            assert all_finite(obs, [reward]), f"{env_id} {name}={value!r}: non-finite step"
            if terminated or truncated:
                env.reset()
    finally:
        env.close()


def mutate(state, data):
    """The state with one leaf replaced by a drawn value, or a key added or removed."""
    if not isinstance(state, dict) or not state:
        return data.draw(values)
    key = data.draw(st.sampled_from(sorted(state)))
    action = data.draw(st.sampled_from(["replace", "drop", "add", "recurse"]))
    out = dict(state)
    if action == "replace":
        out[key] = data.draw(values)
    elif action == "drop":
        del out[key]
    elif action == "add":
        out[data.draw(st.text(max_size=8))] = data.draw(values)
    else:
        out[key] = mutate(out[key], data) if isinstance(out[key], dict) else data.draw(values)
    return out


@SETTINGS
@given(data=st.data())
def test_any_task_state_is_applied_or_refused_in_one_line(envs, data):
    env_id = data.draw(st.sampled_from(sorted(envs)))
    env = envs[env_id]
    base = env.unwrapped.sample_task_state()
    kind = data.draw(st.sampled_from(["mutated", "mutated", "any value"]))
    state = mutate(base, data) if kind == "mutated" else data.draw(values)
    try:
        env.unwrapped.set_task_state(state)
    except ERRORS as error:
        one_line(error)
        env.unwrapped.set_task_state(base)  # a refused state leaves the env usable
        env.reset(seed=0)
        return
    obs, _ = env.reset(seed=0)
    assert all_finite(obs)
    obs, reward, *_ = env.step(env.action_space.sample())
    assert all_finite(obs, [reward])
    # what was accepted reads back and is accepted again
    env.unwrapped.set_task_state(env.unwrapped.get_task_state())
    assert not math.isnan(float(reward))
