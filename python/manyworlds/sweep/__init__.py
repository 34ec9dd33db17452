"""Sweeps, searches and statistics of `manyworlds train` runs on Ray (the `sweep` extra).

    pip install '.[sweep]'           # ray[tune], rliable, tensorboardX, matplotlib, pyyaml
    manyworlds-sweep run SWEEP.yaml  # every run of a sweep file, on a local Ray instance
    manyworlds-sweep report runs/sweeps/NAME   # IQM and 95 % intervals with rliable

Modules: spec (sweep files), runner (the Ray tasks and their resumption), tune (Ray Tune
search), report (rliable statistics, tables, plots), tensorboard (event files of runs), cli.
Importing this package imports none of the extra's dependencies.
"""
