"""Every hostile input of issue 12 (tests/hostile_corpus.py) through the `floorscan` command,
each in its own process: exit code, stderr lines, traceback or not, temporary files left,
peak resident memory (the child's ru_maxrss) and wall time. Prints a Markdown table and the
totals (panics, aborts, tracebacks, hangs, cases over 1 GB).

Run: .venv/bin/python bench/hostile_inputs.py
     FLOORSCAN_EXE=/path/to/other/floorscan .venv/bin/python bench/hostile_inputs.py  (another build)
"""

from __future__ import annotations

import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))

import hostile_corpus as hc  # noqa: E402


def main() -> None:
    with tempfile.TemporaryDirectory() as d:
        root = Path(d)
        shared = hc.make_shared(root / "shared")
        rows = []
        for case in hc.CASES:
            r = hc.run_case(case, root / case.name, shared)
            rows.append((case, r))
    print("| case | exit | stderr lines | traceback | temp files | peak RSS MB | s |")
    print("|---|---:|---:|---|---|---:|---:|")
    for case, r in rows:
        rc = "hang" if r.hang else str(r.rc)
        print(
            f"| {case.name} | {rc} | {len(r.stderr_lines)} | {'yes' if r.traceback else 'no'} "
            f"| {len(r.temp_files)} | {r.peak_rss_mb:.0f} | {r.seconds:.1f} |"
        )
    results = [r for _, r in rows]
    aborts = sum(1 for r in results if r.rc is not None and r.rc < 0)
    panics = sum(1 for r in results if "PanicException" in r.stderr or "panicked" in r.stderr)
    tracebacks = sum(1 for r in results if "Traceback" in r.stderr)
    hangs = sum(1 for r in results if r.hang)
    unexpected = sum(1 for c, r in rows if r.rc not in c.exit_codes)
    temps = sum(1 for r in results if r.temp_files)
    over = sum(1 for r in results if r.peak_rss_mb >= hc.PEAK_RSS_BUDGET_MB)
    peak = max(r.peak_rss_mb for r in results)
    print(
        f"\n{len(results)} cases: {panics} panics, {aborts} aborts (killed by a signal), "
        f"{tracebacks} tracebacks, {hangs} hangs, {unexpected} unexpected exit codes, "
        f"{temps} with temporary files left, {over} over {hc.PEAK_RSS_BUDGET_MB:.0f} MB; "
        f"largest peak RSS {peak:.0f} MB"
    )


if __name__ == "__main__":
    main()
