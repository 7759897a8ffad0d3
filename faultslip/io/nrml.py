"""Predicted segments as an OpenQuake source model (NRML 0.5 simple-fault sources).

Each segment becomes a ``simpleFaultSource``: its trace (``gml:LineString``), dip, upper and lower
seismogenic depths (km), rake, the Wells & Coppersmith (1994) magnitude-scaling relation and a
rupture aspect ratio of 2, and a magnitude-frequency distribution built from the prediction:

- ``characteristic``: one bin of width 0.1 at the predicted Mw, with the annual rate 1/T
  (an ``incrementalMFD``). Its moment rate is M0(Mw)/T = G L H V: moment-balanced by construction.
- ``truncated_gr``: a ``truncGutenbergRichterMFD`` with b = 1 from Mw - 1 to Mw + 0.1, its a-value
  set so that its moment rate equals the characteristic one (moment balance, with
  M0 = 10^(1.5 Mw + 9.1) N m).

The file is written atomically. The tests parse it back and check the structure, and, where the
OpenQuake engine is installed, load it with ``openquake.hazardlib.nrml``.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import numpy as np

from faultslip.errors import InputError
from faultslip.io.atomic import atomic_path
from faultslip.units import JULIAN_YEAR

NRML_NAMESPACE = "http://openquake.org/xmlschema/nrml/0.5"
GML_NAMESPACE = "http://www.opengis.net/gml"
MFD_KINDS = ("characteristic", "truncated_gr")
YEAR = JULIAN_YEAR
B_VALUE = 1.0


def _moment(magnitude):
    return 10.0 ** (1.5 * np.asarray(magnitude, dtype=float) + 9.1)


def gutenberg_richter_a_value(moment_rate: float, min_magnitude: float, max_magnitude: float,
                              b_value: float = B_VALUE) -> float:
    """The a-value whose truncated Gutenberg-Richter distribution, with annual rate density
    n(m) = b ln10 10^(a - b m) on [min, max], releases ``moment_rate`` (N m per year)."""
    magnitudes = np.linspace(min_magnitude, max_magnitude, 2001)
    per_unit_a = b_value * math.log(10.0) * 10.0 ** (-b_value * magnitudes) * _moment(magnitudes)
    integral = float(np.sum(0.5 * (per_unit_a[1:] + per_unit_a[:-1]) * np.diff(magnitudes)))
    return math.log10(moment_rate / integral)


def write_source_model(path, segments: list[dict], name: str, mfd: str = "characteristic",
                       tectonic_region: str = "Active Shallow Crust") -> int:
    """Write ``segments`` (dicts: id, name, trace (n, 2) lon/lat, dip, rake, upper_depth and lower_depth in m,
    magnitude, recurrence in s) as NRML; segments without stick-slip (no magnitude or recurrence) are left
    out. Returns how many sources were written."""
    if mfd not in MFD_KINDS:
        raise InputError(f"the magnitude-frequency distribution must be one of {', '.join(MFD_KINDS)}, got {mfd!r}")
    ET.register_namespace("", NRML_NAMESPACE)
    ET.register_namespace("gml", GML_NAMESPACE)
    nrml = ET.Element(f"{{{NRML_NAMESPACE}}}nrml")
    model = ET.SubElement(nrml, f"{{{NRML_NAMESPACE}}}sourceModel", name=name)
    group = ET.SubElement(model, f"{{{NRML_NAMESPACE}}}sourceGroup", name="faultslip predictions",
                          tectonicRegion=tectonic_region)
    written = 0
    for segment in segments:
        magnitude, recurrence = segment["magnitude"], segment["recurrence"]
        if not (magnitude is not None and math.isfinite(magnitude) and recurrence is not None
                and math.isfinite(recurrence) and recurrence > 0):
            continue
        source = ET.SubElement(group, f"{{{NRML_NAMESPACE}}}simpleFaultSource", id=str(segment["id"]),
                               name=str(segment["name"]), tectonicRegion=tectonic_region)
        geometry = ET.SubElement(source, f"{{{NRML_NAMESPACE}}}simpleFaultGeometry")
        line = ET.SubElement(geometry, f"{{{GML_NAMESPACE}}}LineString")
        ET.SubElement(line, f"{{{GML_NAMESPACE}}}posList").text = " ".join(
            f"{lon:.5f} {lat:.5f}" for lon, lat in np.asarray(segment["trace"], dtype=float))
        ET.SubElement(geometry, f"{{{NRML_NAMESPACE}}}dip").text = f"{segment['dip']:g}"
        ET.SubElement(geometry, f"{{{NRML_NAMESPACE}}}upperSeismoDepth").text = f"{segment['upper_depth'] / 1e3:g}"
        ET.SubElement(geometry, f"{{{NRML_NAMESPACE}}}lowerSeismoDepth").text = f"{segment['lower_depth'] / 1e3:g}"
        ET.SubElement(source, f"{{{NRML_NAMESPACE}}}magScaleRel").text = "WC1994"
        ET.SubElement(source, f"{{{NRML_NAMESPACE}}}ruptAspectRatio").text = "2.0"
        rate = YEAR / recurrence
        if mfd == "characteristic":
            bins = ET.SubElement(source, f"{{{NRML_NAMESPACE}}}incrementalMFD", minMag=f"{magnitude:.3f}",
                                 binWidth="0.1")
            ET.SubElement(bins, f"{{{NRML_NAMESPACE}}}occurRates").text = f"{rate:.6e}"
        else:
            low, high = magnitude - 1.0, magnitude + 0.1
            a_value = gutenberg_richter_a_value(rate * float(_moment(magnitude)), low, high)
            ET.SubElement(source, f"{{{NRML_NAMESPACE}}}truncGutenbergRichterMFD", aValue=f"{a_value:.5f}",
                          bValue=f"{B_VALUE:g}", minMag=f"{low:.3f}", maxMag=f"{high:.3f}")
        ET.SubElement(source, f"{{{NRML_NAMESPACE}}}rake").text = f"{segment['rake']:g}"
        written += 1
    if not written:
        raise InputError("no segment has stick-slip (a magnitude and a recurrence): nothing to write as NRML")
    ET.indent(nrml)
    with atomic_path(path) as temporary:
        ET.ElementTree(nrml).write(temporary, encoding="utf-8", xml_declaration=True)
    return written
