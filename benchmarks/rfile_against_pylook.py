"""faultslip's r-file reduction against pylook's, slot by slot, on Penn State's biax run p655 (issue 46, item 1).

    python benchmarks/rfile_against_pylook.py --pylook-python /tmp/pylook/bin/python

(the interpreter as benchmarks/look_against_pylook.py sets it up: pylook 0.1.1 with the older numpy and pint it
needs). pylook (Leeman Geophysical, BSD-3) runs ``XlookParser().doit('data/p655/p655_r')`` in its own interpreter
and hands back every slot; faultslip runs :func:`faultslip.lab.look_reduction.run_r_file` on the same file. For
every slot either holds, the name, the unit, the number of records and the values are compared, and where values
differ, the records that differ are counted and located, so that each difference can be traced to a command:

* record ranges: pylook reads ``FIRST LAST`` as a Python slice, stopping before LAST (and before the last record
  for -1); faultslip includes LAST, as the r-file's own ``r_row 86283 86283`` ("ax it") requires. So pylook keeps
  record 86283, and its slots are compared with that record removed; its ``math_int`` leaves record 1459 and the
  last record unchanged where faultslip changes them.
* ``ec``: pylook's interpreter subtracts the corrected displacement from the displacement, which leaves the load
  over the stiffness (LOAD / SLOPE), not DISP - LOAD / SLOPE; its own ``elastic_correction`` function is right.
* ``strain``: pylook does not implement it (it warns and goes on), so its slot has no counterpart.

Writes benchmarks/results/rfile_against_pylook.json.
"""

from __future__ import annotations

import json
import sys
import tempfile
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from faultslip.lab.look_reduction import run_r_file  # noqa: E402
from look_against_pylook import in_pylook, pylook_arguments  # noqa: E402
from provenance import stamp  # noqa: E402  (one stamp for every results file)

R_FILE = ROOT / "data" / "p655" / "p655_r"
#: the record the r-file's ``r_row 86283 86283`` removes, which pylook's slice keeps
AXED = 86283
DUMP = """
import json, sys, warnings
import numpy as np
from pylook.io import XlookParser
look = XlookParser()
with warnings.catch_warnings(record=True) as caught:
    warnings.simplefilter("always")
    look.doit(sys.argv[1])
out = {}
for slot in range(look.max_cols):
    values = look.data[slot]
    if look.data_names[slot] is None or values is None or len(values) == 0:
        continue
    np.save(f"{sys.argv[2]}/{slot}.npy", np.asarray(values, dtype=float))
    out[slot] = {"name": look.data_names[slot], "unit": look.data_units[slot]}
print(json.dumps({"slots": out, "warnings": [str(w.message) for w in caught]}))
"""


def main(argv=None):
    args = pylook_arguments(__doc__.split("\n\n")[0]).parse_args(argv)
    ours = run_r_file(R_FILE)
    with tempfile.TemporaryDirectory() as folder:
        theirs, version = in_pylook(args.pylook_python, DUMP, R_FILE, folder)
        rows = []
        for slot in range(len(ours.data)):
            mine = ours.data[slot]
            entry = theirs["slots"].get(str(slot))
            if mine is None and entry is None:
                continue
            row = {"slot": slot, "name_faultslip": ours.names[slot], "unit_faultslip": ours.units[slot],
                   "records_faultslip": None if mine is None else int(mine.size)}
            if entry is None:
                row["in_pylook"] = False
                rows.append(row)
                continue
            values = np.load(Path(folder) / f"{slot}.npy")
            row.update(in_pylook=True, name_pylook=entry["name"], unit_pylook=entry["unit"],
                       records_pylook=int(values.size))
            if mine is not None and values.size == mine.size + 1:  # pylook kept the axed record
                values = np.delete(values, AXED)
            if mine is not None and values.size == mine.size:
                differ = ~((values == mine) | (np.isnan(values) & np.isnan(mine)))
                where = np.flatnonzero(differ)
                row.update(identical=bool(where.size == 0), records_differing=int(where.size),
                           first_differing=[int(i) for i in where[:3]], last_differing=int(where[-1]) if where.size
                           else None, largest_difference=float(np.nanmax(np.abs(values - mine))) if where.size
                           else 0.0)
            rows.append(row)
    result = {"r_file": "data/p655/p655_r", "pylook": version, "axed_record": AXED, "slots": rows,
              "pylook_warnings": theirs["warnings"], "commands_faultslip": ours.commands,
              **stamp()}
    out = ROOT / "benchmarks" / "results" / "rfile_against_pylook.json"
    out.write_text(json.dumps(result, indent=1) + "\n", encoding="utf-8")
    for row in rows:
        print(row)
    print("pylook's warnings:", *theirs["warnings"], sep="\n  ")
    print(f"written to {out}")


if __name__ == "__main__":
    main()
