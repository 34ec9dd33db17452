"""Meta-World v3's own evaluation functions driving our envs (run by test_metaworld_protocols.py).

Runs with the official package's Python ($MANYWORLDS_METAWORLD_PYTHON) and our package on its
path: v3's ``metaworld.evaluation.metalearning_evaluation`` or ``evaluation``, unchanged, over our
vector env (``manyworlds.metaworld_gym``) with ``manyworlds.evaluation.PolicyAgent``. Prints one
JSON object: the mean success rate and return and the success rate of each task (v3's names),
and ``class_names_match``: whether every task's ``task_name`` is v3's env class of that task.

    python metaworld_protocols.py '{"protocol": "meta-test", "benchmark": "ML10",
        "policy": "scripted", "seed": 1,
        "meta_batch_size": 10, "total_tasks_per_cls": 2, "num_evals": 1,
        "adaptation_episodes": 1, "evaluation_episodes": 3}'
    python metaworld_protocols.py '{"protocol": "multi-task", "policy": "random", "seed": 1,
        "episodes": 1}'
"""

import json
import sys
from functools import partial

import metaworld.evaluation as v3
from metaworld.env_dict import ALL_V3_ENVIRONMENTS

from manyworlds import benchmarks, metaworld_gym
from manyworlds.evaluation import PolicyAgent


def main():
    args = json.loads(sys.argv[1])
    if args["protocol"] == "meta-test":
        # an ML benchmark's test split (ML10, or ML1 of a task), meta_batch_size envs, each with
        # total_tasks_per_cls / envs-per-task goals
        envs = metaworld_gym.make_ml_envs(
            args["benchmark"], split="test", meta_batch_size=args["meta_batch_size"],
            total_tasks_per_cls=args["total_tasks_per_cls"], task_select="pseudorandom")
        agent = PolicyAgent(envs, args["policy"], args["seed"])
        success, mean_return, per_task = v3.metalearning_evaluation(
            agent, envs, num_evals=args["num_evals"], adaptation_steps=1,
            adaptation_episodes=args["adaptation_episodes"],
            evaluation_episodes=args["evaluation_episodes"])
    else:
        # MT10 with each task's first goal (the multi-task config's variations_per_task: 1)
        bench = benchmarks.MT10()
        fns = []
        for env_id, (name, env_cls) in enumerate(bench.train_classes.items()):
            first = next(t for t in bench.train_tasks if t.env_name == name)
            fns.append(partial(metaworld_gym._init_each_env, env_cls=env_cls, tasks=[first],
                               env_id=env_id, num_tasks=len(bench.train_classes)))
        envs = metaworld_gym._vector_env(fns, "sync", None)
        agent = PolicyAgent(envs, args["policy"], args["seed"])
        success, mean_return, per_task, _ = v3.evaluation(agent, envs, args["episodes"])
    names = {cls.__name__: name for name, cls in ALL_V3_ENVIRONMENTS.items()}
    ours = [(env.unwrapped.TASK_NAME, env.unwrapped.task_name) for env in envs.envs]
    match = all(names.get(class_name) == task + "-v3" for task, class_name in ours)
    print(json.dumps({"success": float(success), "return": float(mean_return),
                      "per_task": {k: float(v) for k, v in per_task.items()},
                      "class_names_match": match}))


if __name__ == "__main__":
    main()
