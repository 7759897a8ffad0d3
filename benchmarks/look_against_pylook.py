"""faultslip's xlook reader against pylook's, column by column, on Penn State's biax run p655 (issue 46, item 1).

    python -m venv /tmp/pylook && /tmp/pylook/bin/pip install pylook==0.1.1 "numpy<1.25" "matplotlib<3.8" "pint<0.18"
    python benchmarks/look_against_pylook.py --pylook-python /tmp/pylook/bin/python

(pylook 0.1.1, its newest release, imports ``pint.unit`` and calls ``numpy.cumproduct``, which today's pint and
numpy no longer have: its interpreter gets the older ones.)

pylook (Leeman Geophysical, BSD-3) is run in its own interpreter, so nothing of it enters faultslip's; it reads
data/p655/p655intact100l with ``pylook.io.read_binary`` and hands its columns back as a .npy file per column.
faultslip reads the same file with :func:`faultslip.lab.look_files.read_look`. Every column's name, unit, length
and values are compared. Writes benchmarks/results/look_against_pylook.json, which tests/capabilities/lab/test_look_files.py reads.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

from faultslip.lab.look_files import read_look  # noqa: E402
from provenance import stamp  # noqa: E402  (one stamp for every results file)

FILE = ROOT / "data" / "p655" / "p655intact100l"
DUMP = """
import json, sys
import numpy as np
from pylook.io import read_binary
data, metadata = read_binary(sys.argv[1])
out = {}
for index, (name, column) in enumerate(data.items()):
    np.save(f"{sys.argv[2]}/{index}.npy", np.asarray(column.magnitude, dtype=float))
    out[name] = {"file": f"{index}.npy", "units": str(column.units)}
print(json.dumps({"columns": out, "name": metadata.get("name"), "records": metadata["number of records"]}))
"""


def in_pylook(python: str, script: str, target: Path, folder: str) -> tuple[dict, str]:
    """Run ``script`` in pylook's own interpreter on ``target``, its arrays dumped in ``folder``: (the JSON it
    prints last, pylook's version)."""
    done = subprocess.run([python, "-c", script, str(target), folder], capture_output=True, text=True, check=True)
    version = subprocess.run([python, "-c", "import pylook; print(pylook.__version__)"], capture_output=True,
                             text=True, check=True).stdout.strip()
    return json.loads(done.stdout.strip().splitlines()[-1]), version


def pylook_arguments(description: str):
    parser = argparse.ArgumentParser(description=description)
    parser.add_argument("--pylook-python", required=True, help="an interpreter with pylook installed")
    return parser


def main(argv=None):
    args = pylook_arguments(__doc__.split("\n\n")[0]).parse_args(argv)
    ours = read_look(FILE)
    with tempfile.TemporaryDirectory() as folder:
        theirs, version = in_pylook(args.pylook_python, DUMP, FILE, folder)
        rows = []
        for name, column in ours.columns.items():
            entry = theirs["columns"].get(name)
            if entry is None:
                rows.append({"column": name, "in_pylook": False})
                continue
            values = np.load(Path(folder) / entry["file"])
            rows.append({"column": name, "in_pylook": True, "records": int(values.size),
                         "largest_difference": float(np.max(np.abs(values - column))) if values.size == column.size
                         else None, "bit_identical": bool(values.size == column.size and np.array_equal(values, column)),
                         "unit_faultslip": ours.units[name], "unit_pylook": entry["units"]})
    result = {"file": "data/p655/p655intact100l", "pylook": version, "name": [ours.name, theirs["name"]],
              "records": [ours.records, theirs["records"]], "columns": rows,
              "only_in_pylook": sorted(set(theirs["columns"]) - set(ours.columns) - {"rec_num"}),
              **stamp()}
    out = ROOT / "benchmarks" / "results" / "look_against_pylook.json"
    out.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    for row in rows:
        print(row)
    print(f"written to {out}")


if __name__ == "__main__":
    main()
