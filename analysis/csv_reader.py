"""Speed of the one CSV reader: the checked pandas path against the cell-by-cell parser, and
against a plain ``pandas.read_csv`` (the unchecked path of earlier versions).

Both parse the same file (a planned PUMA 560 trajectory, N set points, full header); runs are
interleaved, the same number on each side; the median and range of each and of their ratio are
printed. Also checks that both give identical arrays.

    python analysis/csv_reader.py [N] [REPEATS]
"""

import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from gd_analyze import load_robot
from gd_analyze.trajectory import trajectory as tr


def main(n_setpoints=200_000, repeats=5):
    robot = load_robot("puma560")
    traj = tr.plan_quintic(robot, np.radians(tr.DEFAULT_START_DEG),
                           np.radians(tr.DEFAULT_GOAL_DEG), n_setpoints)
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "t.csv"
        tr.write_trajectory(traj, path)
        raw = path.read_bytes()
        import pandas as pd

        fast, slow, plain = [], [], []
        for _ in range(repeats):
            t0 = time.perf_counter()
            pd.read_csv(path, dtype=float, engine="c").to_numpy()
            plain.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            with open(path, "rb") as fh:
                a = tr.streamed_values(fh, str(path), lambda fields: fields)
            fast.append(time.perf_counter() - t0)
            t0 = time.perf_counter()
            b = tr._validated_values(raw, str(path), 6)
            slow.append(time.perf_counter() - t0)
        assert a is not None and np.array_equal(a[0], b[0])
    ratios = [s / f for f, s in zip(fast, slow)]
    print(f"{n_setpoints} set points, {len(raw) / 1e6:.1f} MB, {repeats} interleaved runs each")
    print(f"checked pandas path: median {statistics.median(fast):.3f} s "
          f"(range {min(fast):.3f}-{max(fast):.3f})")
    print(f"cell-by-cell parser: median {statistics.median(slow):.3f} s "
          f"(range {min(slow):.3f}-{max(slow):.3f})")
    over = [f / p for f, p in zip(fast, plain)]
    print(f"plain pandas.read_csv: median {statistics.median(plain):.3f} s "
          f"(range {min(plain):.3f}-{max(plain):.3f}); checked / plain: median "
          f"{statistics.median(over):.2f} (range {min(over):.2f}-{max(over):.2f})")
    print(f"cell-by-cell / pandas: median {statistics.median(ratios):.1f} "
          f"(range {min(ratios):.1f}-{max(ratios):.1f}); identical arrays: yes")


if __name__ == "__main__":
    main(*(int(a) for a in sys.argv[1:3]))
