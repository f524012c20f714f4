"""Convert the TIAGo recording (FIGAROH, Apache-2.0) into the identify CSV format.

The three source files (``tiago_position.csv``, ``tiago_velocity.csv``, ``tiago_effort.csv``:
a header ``t`` then ``- <joint>_position`` etc., the same clock) become
``t,q1..q8,tau1..tau8,qd1..qd8`` with joints in the order torso_lift_joint, arm_1_joint ..
arm_7_joint (the chain of example-robot-data's tiago.urdf). Rows FIT go to
``data/tiago/tiago_fit.csv``, rows VALIDATE to ``data/tiago/tiago_validate.csv``; numbers with
10 significant digits. Run from the repository's root::

    .venv/bin/python analysis/convert_tiago.py [SOURCE_FOLDER]
"""

import hashlib
import json
import pathlib
import sys

import numpy as np
import pandas as pd

SOURCE = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else "../../shared/recordings/tiago")
OUT = pathlib.Path("data/tiago")
JOINTS = ["torso_lift_joint"] + [f"arm_{k}_joint" for k in range(1, 8)]
#: Source rows (0-based, after the header) of the two parts: fit on the first, validate on the
#: last; the standstill at the start and the end of the recording is left out.
FIT = slice(400, 4400)
VALIDATE = slice(4400, 6900)


def _read(kind):
    path = SOURCE / f"tiago_{kind}.csv"
    frame = pd.read_csv(path)
    cols = [f"- {j}_{kind}" for j in JOINTS]
    return frame["t"].to_numpy(), frame[cols].to_numpy(), hashlib.sha256(
        path.read_bytes()).hexdigest()


def main():
    t, q, hq = _read("position")
    t2, qd, hv = _read("velocity")
    t3, tau, he = _read("effort")
    assert np.array_equal(t, t2) and np.array_equal(t, t3)
    n = len(JOINTS)
    header = ",".join(["t"] + [f"q{i}" for i in range(1, n + 1)]
                      + [f"tau{i}" for i in range(1, n + 1)]
                      + [f"qd{i}" for i in range(1, n + 1)])
    OUT.mkdir(parents=True, exist_ok=True)
    written = {}
    for name, rows in (("tiago_fit.csv", FIT), ("tiago_validate.csv", VALIDATE)):
        values = np.hstack([t[rows, None], q[rows], tau[rows], qd[rows]])
        text = header + "\n" + "\n".join(",".join(f"{v:.10g}" for v in row)
                                         for row in values) + "\n"
        (OUT / name).write_text(text)
        written[name] = {"source_rows": [rows.start + 2, rows.stop + 1],
                         "sha256": hashlib.sha256(text.encode()).hexdigest()}
    provenance = {
        "source": "GitHub thanhndv212/figaroh-examples, examples/tiago/data/identification/"
                  "dynamic/ (the FIGAROH project), via ../shared/recordings/tiago",
        "licence": "Apache-2.0 (LICENSE in this folder)",
        "source_sha256": {"tiago_position.csv": hq, "tiago_velocity.csv": hv,
                          "tiago_effort.csv": he},
        "joints": JOINTS,
        "robot": "example-robot-data tiago_description/robots/tiago.urdf (chain to arm_7_link)",
        "units": "t [s], q [m for the torso, rad], tau: the controller's effort signal (its "
                 "scale to N m is uncertain by 10-20 %, FIGAROH's notes), qd [m/s, rad/s]",
        "converted_by": "analysis/convert_tiago.py",
        "files": written,
    }
    (OUT / "provenance.json").write_text(json.dumps(provenance, indent=2) + "\n")


if __name__ == "__main__":
    main()
