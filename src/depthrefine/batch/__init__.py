"""Many frames at once: scheduling on Dask distributed, in order, with an optional warm start.

The same code path serves one machine and a cluster: frames (or, with
``temporal``, chunks of consecutive frames) are tasks of a
``dask.distributed`` client, which is either given (``client=``, e.g.
``Client("tcp://scheduler:8786")``) or a :class:`distributed.LocalCluster`
started for the run (processes with one thread each, one per core).

Images travel to the workers inside their tasks and results come back as
arrays: the workers need the package but no access to the files. A worker
lost mid-run has its frames recomputed on another (:mod:`._schedule`).

- :func:`refine_many`: registered pairs in, refined depth out, in order.
- :class:`BatchJob`: what ``depthrefine batch`` runs: a sequence of frames
  (:func:`depthrefine.io.open_sequence`) into an output folder, with the rig
  chain for raw captures, resume, ``batch.json`` and a preview video.

Without ``temporal`` each frame is refined on its own, exactly as
:func:`depthrefine.refine` refines it (bit for bit). With ``temporal`` the
frames of a chunk run in order on one worker and each warm-starts from the
state the method left after the previous one (the thesis method: its
k-means starts from the previous frame's means, so cluster labels do not
flicker); a method without :attr:`Method.refine_stateful` runs each frame on
its own. Chunks are cut from the whole sequence at fixed positions
(``chunk`` frames each), so the result does not depend on the number of
workers or on a restart.

Dask is imported only when a batch runs.
"""

from ._frame import FrameOutput, FramePlan, solve_frame
from ._job import BatchJob, BatchOptions, BatchSummary
from ._schedule import DEFAULT_CHUNK, ClusterLost, FrameResult, local_client, needed_keys, refine_many, run_frames

__all__ = ["refine_many", "BatchJob", "BatchOptions", "BatchSummary", "ClusterLost", "FramePlan", "FrameOutput",
           "FrameResult", "solve_frame", "run_frames", "local_client", "needed_keys", "DEFAULT_CHUNK"]
