"""The fleet's recordings as Ray tasks: one task per recording, re-run by Ray when its worker
dies (``max_retries``), results gathered as they finish, Ctrl-C cancelling what is left."""

from __future__ import annotations

from pathlib import Path
from typing import Any, Dict, List, Optional

from ..errors import OptionError


def import_ray():
    try:
        import ray
    except ImportError:
        raise OptionError(
            "--ray needs the `ray` package: pip install 'floorscan[fleet]' (or pip install ray)"
        ) from None
    return ray


def connect(ray, address: str, workers: Optional[int]) -> bool:
    """Connects this process to Ray; True if it started (and so must stop) the instance."""
    if ray.is_initialized():
        return False
    kw: Dict[str, Any] = dict(include_dashboard=False, log_to_driver=False, logging_level="ERROR")
    if address == "local":
        if workers is not None and workers < 1:
            raise OptionError(f"invalid option `workers`: must be >= 1, got {workers}")
        ray.init(num_cpus=workers, **kw)
    else:
        if workers is not None:
            raise OptionError("`workers` is for --ray local; a cluster has its own")
        try:
            ray.init(address=address, **kw)
        except (ConnectionError, RuntimeError, ValueError) as e:
            raise OptionError(f"cannot join the Ray cluster at {address!r}: {e}") from None
    return True


WAIT_S = 0.5
"""Longest wait for a task between two looks at signals [s]."""


def map_on_ray(recs, out: Path, map_one, bar, address: str, workers, max_retries: int):
    """(results in the order of ``recs``, interrupted)."""
    ray = import_ray()
    started = connect(ray, address, workers)
    try:
        task = ray.remote(num_cpus=1, max_retries=max_retries)(map_one)
        refs = {task.remote(r, str(out / r.name)): k for k, r in enumerate(recs)}
        results: List[Optional[Dict[str, Any]]] = [None] * len(recs)
        pending = list(refs)
        interrupted = False
        try:
            while pending:
                # A timeout, so that Python runs (and a Ctrl-C is raised) at least twice a
                # second even while ray.wait would block in native code.
                ready, pending = ray.wait(pending, num_returns=1, timeout=WAIT_S)
                for ref in ready:
                    k = refs[ref]
                    results[k] = _outcome(ray, ref, recs[k])
                bar.update([r for r in results if r is not None])
        except KeyboardInterrupt:
            interrupted = True
            for ref in pending:
                ray.cancel(ref, force=True)
                r = recs[refs[ref]]
                results[refs[ref]] = {
                    "name": r.name,
                    "input": r.input,
                    "status": "cancelled",
                    "error": "Ctrl-C",
                }
        return [r for r in results if r is not None], interrupted
    finally:
        if started:
            ray.shutdown()


def _outcome(ray, ref, rec) -> Dict[str, Any]:
    try:
        return ray.get(ref)
    except ray.exceptions.RayError as e:
        # The worker died more often than max_retries allows, or the task was cancelled.
        first = str(e).strip().splitlines()[0] if str(e).strip() else ""
        return {
            "name": rec.name,
            "input": rec.input,
            "status": "failed",
            "error": f"{type(e).__name__}: {first}",
        }
