"""
Running on a Dask cluster, and resuming
=======================================

A study's jobs (one per case, split by order where large) run on any Dask cluster:
``harness.DaskEngine(scheduler="tcp://host:8786")``, or ``--scheduler`` on the command
line. Here a cluster inside this process (one worker thread) stands in for one; on a real
cluster, ``dask scheduler`` and ``dask worker tcp://host:8786 --nthreads 1`` on each machine, or
``DaskEngine(workers=N)`` for N local worker processes. With a checkpoint folder
every finished level is durable: a study killed and run again resumes where it stopped, and a
study run again after it finished recomputes nothing.
"""

# %%
import logging
import tempfile
import time
from pathlib import Path

from distributed import LocalCluster

import harness

logging.getLogger("distributed").setLevel(logging.ERROR)      # the cluster's own chatter
cluster = LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=":0",
                       silence_logs=logging.ERROR)
engine = harness.DaskEngine(scheduler=cluster.scheduler_address)
checkpoints = Path(tempfile.mkdtemp()) / "checkpoints"
clock = time.perf_counter()
rows = harness.run(["transition-r32", "corner-r12"], methods=["paper"], levels=3, engine=engine,
                   checkpoints=checkpoints, show_progress=False)
print(f"{len(rows)} rows in {time.perf_counter() - clock:.1f} s", engine.describe())

# %%
# The same study again: every level is read from the checkpoints, the rows are the same.
clock = time.perf_counter()
again = harness.run(["transition-r32", "corner-r12"], methods=["paper"], levels=3, engine=engine,
                    checkpoints=checkpoints, show_progress=False)
print(f"again: {len(again)} rows in {time.perf_counter() - clock:.1f} s;",
      "same errors:", bool((again.sort_values(["case", "method", "level"]).err_h1.values
                           == rows.sort_values(["case", "method", "level"]).err_h1.values).all()))
engine.close()
cluster.close()
