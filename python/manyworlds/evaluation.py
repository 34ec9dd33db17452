"""Agents for Meta-World v3's evaluation functions that act with the envs' own policies.

v3's ``metaworld.evaluation.evaluation(agent, envs, num_episodes)`` and
``metalearning_evaluation(agent, envs, ...)`` take any agent with v3's ``Agent`` /
``MetaLearningAgent`` methods. :class:`PolicyAgent` is one over our vector envs
(``manyworlds.metaworld_gym.make_mt_envs`` / ``make_ml_envs``, or
``gymnasium.make_vec("manyworlds-Meta-World/...")``) that acts with each env's scripted (expert)
policy or with uniform random actions, so that v3's own protocol code can score our envs::

    import metaworld.evaluation as v3
    from manyworlds.metaworld_gym import make_ml_envs
    from manyworlds.evaluation import PolicyAgent

    envs = make_ml_envs("ML10", split="test", meta_batch_size=10, total_tasks_per_cls=2)
    success, mean_return, per_task = v3.metalearning_evaluation(
        PolicyAgent(envs, "scripted"), envs, num_evals=1, adaptation_episodes=1)

It is the Python twin of ``manyworlds eval CONFIG --policy scripted|random``
(experiments/evaluation/policy_actor.h): env i's random policy draws from the stream
``mix_seed(seed, i)``, and a policy starts an episode wherever its env is at step 0, so both
sides act alike step for step (``python/tests/test_metaworld_protocols.py`` checks that they
score the same). Needs a ``SyncVectorEnv`` (the agent reads each env's task).
"""

from __future__ import annotations

from typing import Any, Dict, List, Tuple

import numpy as np

from manyworlds import _core

__all__ = ["PolicyAgent"]


class PolicyAgent:
    """v3's ``Agent`` and ``MetaLearningAgent`` over each env's scripted or random policy.

    ``policy``: ``"scripted"`` or ``"random"``; ``seed``: the random policies' seed. Adaptation
    does nothing: the policies do not learn.
    """

    def __init__(self, envs: Any, policy: str = "scripted", seed: int = 0) -> None:
        if policy not in ("scripted", "random"):
            raise ValueError(f"policy must be 'scripted' or 'random', got {policy!r}")
        if not hasattr(envs, "envs"):
            raise ValueError("PolicyAgent needs a SyncVectorEnv (it reads each env's task)")
        self._envs = [env.unwrapped for env in envs.envs]
        self._policy = policy
        self._seed = int(seed)
        self._policies: List[Any] = [None] * len(self._envs)

    def _policy_of(self, i: int) -> Any:
        if self._policies[i] is None:
            core = self._envs[i]._live()
            self._policies[i] = (_core.scripted_policy(core) if self._policy == "scripted"
                                 else _core.random_policy(core, _core.mix_seed(self._seed, i)))
        return self._policies[i]

    def _act(self, observations: np.ndarray) -> np.ndarray:
        actions = []
        for i, env in enumerate(self._envs):
            policy = self._policy_of(i)
            if env.elapsed_steps == 0:
                policy.begin_episode()
            obs = np.asarray(observations[i], dtype=np.float32)
            actions.append(policy.act(obs[: env.observation_space.shape[0]]))
        return np.stack(actions)

    # v3's Agent
    def eval_action(self, observations: np.ndarray) -> np.ndarray:
        return self._act(observations)

    def reset(self, env_mask: np.ndarray) -> None:
        """Nothing to do: a policy starts an episode when its env is at step 0."""

    # v3's MetaLearningAgent
    def init(self) -> None:
        """Nothing to do: the policies keep no memory across rounds."""

    def adapt_action(self, observations: np.ndarray) -> Tuple[np.ndarray, Dict[str, np.ndarray]]:
        return self._act(observations), {}

    def step(self, timestep: Any) -> None:
        """Nothing to do: the policies do not learn from what they see."""

    def adapt(self) -> None:
        """Nothing to do: the policies do not adapt."""
