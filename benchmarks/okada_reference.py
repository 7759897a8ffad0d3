"""Reference tractions of rectangular dislocations from Okada's own code (DC3D, Okada 1992, BSSA 82, 1018), for
the 3-D fault's kernel test (tests/models/fault_3d/test_fault_3d.py).

Okada's Fortran is built by okada_wrapper (pip install okada_wrapper, which needs gfortran); this script evaluates
it for unit strike slip and unit dip slip on squares of a vertical fault at the centres of others, near and far,
surface-breaking and buried, and writes tests/data/okada_dc3d_reference.json with the versions. The test compares
faultslip's kernel (three triangular dislocations a square, cutde) with these numbers; nothing here is typed in.

    python benchmarks/okada_reference.py
"""

from __future__ import annotations

import importlib.metadata
import json
import sys
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))
from provenance import stamp  # noqa: E402  (one stamp for every results file)

SHEAR_MODULUS = 3.2038e10
POISSON_RATIO = 0.25
ELEMENT = 1000.0
#: (source square's strike index, dip index) -> observation squares' (strike offset, dip index)
SOURCES = [(0, 0), (0, 3), (0, 11)]
OBSERVATIONS = [(0, 0), (0, 1), (1, 0), (-1, 2), (3, 3), (0, 3), (7, 10), (-20, 5), (2, 11), (0, 12)]


def okada_traction(observation, source_dip_index, slip: str) -> float:
    """Shear traction along the slip on the plane y = 0 at ``observation`` (x, depth) from unit slip on the square
    [0, h] x [j h, (j + 1) h] of a vertical fault (Okada's frame: x along strike, z up)."""
    from okada_wrapper import dc3dwrapper

    lam = 2 * SHEAR_MODULUS * POISSON_RATIO / (1 - 2 * POISSON_RATIO)
    alpha = (lam + SHEAR_MODULUS) / (lam + 2 * SHEAR_MODULUS)
    top, bottom = source_dip_index * ELEMENT, (source_dip_index + 1) * ELEMENT
    x, depth = observation
    dislocation = [1.0, 0.0, 0.0] if slip == "strike" else [0.0, 1.0, 0.0]
    values = []
    for side in (1e-9, -1e-9):  # either face of the plane: the traction is continuous across it
        success, _, gradient = dc3dwrapper(alpha, [x, side, -depth], bottom, 90.0, [0.0, ELEMENT],
                                           [0.0, bottom - top], dislocation)
        if success != 0:
            raise RuntimeError(f"DC3D returned {success} at {observation}")
        strain = 0.5 * (gradient + gradient.T)
        stress = 2 * SHEAR_MODULUS * strain + lam * np.trace(strain) * np.eye(3)
        values.append(stress[0, 1] if slip == "strike" else stress[2, 1])
    return float(np.mean(values))


def main() -> None:
    rows = []
    for strike_index, dip_index in SOURCES:
        for offset, row in OBSERVATIONS:
            observation = ((offset + 0.5) * ELEMENT, (row + 0.5) * ELEMENT)
            for slip in ("strike", "dip"):
                rows.append({"source": [strike_index, dip_index], "observation": [offset, row], "slip": slip,
                             "okada_stress": okada_traction(observation, dip_index, slip)})
    document = {"what": "sigma_xy (strike slip) and sigma_zy (dip slip) on the plane y = 0, Pa, from unit slip on "
                        "one square of a vertical fault, Okada's DC3D (SI units, z up, the square's top edge at "
                        "dip_index h deep)",
                "shear_modulus": SHEAR_MODULUS, "poisson_ratio": POISSON_RATIO, "element_size": ELEMENT,
                "okada_wrapper": importlib.metadata.version("okada_wrapper"), "rows": rows, **stamp()}
    path = Path(__file__).resolve().parent.parent / "tests" / "data" / "okada_dc3d_reference.json"
    path.write_text(json.dumps(document, indent=1) + "\n", encoding="utf-8")
    print(f"{len(rows)} tractions written to {path}")


if __name__ == "__main__":
    main()
