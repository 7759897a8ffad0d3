"""Fault sources as an OpenQuake source model, and a logic tree over source models (NRML 0.5).

Each segment becomes a ``simpleFaultSource``: its trace (``gml:LineString``), dip, upper and lower
seismogenic depths (km), its magnitude-scaling relation (``WC1994`` unless given), a rupture aspect
ratio of 2, its rake, and its magnitude-frequency distribution (:mod:`faultslip.fault.mfd`, passed in
built): an ``incrementalMFD`` (first bin centre and width, one annual rate per bin) or a
``truncGutenbergRichterMFD`` (a- and b-value and bounds on the bin edges; the engine bins it by the job's
``width_of_mfd_bin``, which must then equal the distribution's bin width). Rates and a-values are written
to ten significant digits, so the moment rate a reader sums back holds to 1e-9.

A fault system's rupture set is a ``multiFaultSource`` (:func:`write_multi_fault_model`): one
``multiPlanesRupture`` a rupture, naming its sections by index in a ``geometryModel`` of ``kiteSurface``
sections (:func:`write_sections`), each section a profile down dip at every trace vertex. Its annual
rates are written as one-year occurrence probabilities, P0 = exp(-rate), which the engine turns back into
rates with the job's ``infer_occur_rates = true``; a background share goes beside it as an ``areaSource``.

A logic tree (``logicTree``, one ``sourceModel`` branch set) weighs several such source models, one per
magnitude-scaling relation (and per rupture model: segments alone, or the fault system). The namespace is ``http://openquake.org/xmlns/nrml/0.5``, which the engine's
logic-tree reader requires (its source-model parser alone also accepts others). Files are written
atomically; the tests parse every file with the engine's own parser and run a hazard calculation on
them where the engine is installed.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET

import numpy as np

from faultslip.errors import InputError
from faultslip.io.atomic import atomic_path
from faultslip.io.geo import azimuth, destination

NRML_NAMESPACE = "http://openquake.org/xmlns/nrml/0.5"
GML_NAMESPACE = "http://www.opengis.net/gml"
#: the engine's magnitude-scaling relation names a source may carry
ENGINE_SCALING_RELATIONS = ("WC1994", "Leonard2014_Interplate", "Leonard2014_SCR", "Leonard2010_SCR")


def _element(parent, tag: str, text: str | None = None, **attributes):
    node = ET.SubElement(parent, f"{{{NRML_NAMESPACE}}}{tag}", **attributes)
    if text is not None:
        node.text = text
    return node


def _root():
    ET.register_namespace("", NRML_NAMESPACE)
    ET.register_namespace("gml", GML_NAMESPACE)
    return ET.Element(f"{{{NRML_NAMESPACE}}}nrml")


def _write(root, path) -> None:
    ET.indent(root)
    with atomic_path(path) as temporary:
        ET.ElementTree(root).write(temporary, encoding="utf-8", xml_declaration=True)


def _mfd_element(source, mfd) -> None:
    """``mfd`` is a :class:`faultslip.fault.mfd.MagnitudeFrequency` (read by its attributes)."""
    if mfd.kind == "truncated_gr":
        p = mfd.parameters
        _element(source, "truncGutenbergRichterMFD", aValue=f"{p['a_value']:.10f}", bValue=f"{p['b_value']:.10g}",
                 minMag=f"{p['min_magnitude_edge']:.10g}", maxMag=f"{p['max_magnitude_edge']:.10g}")
        return
    bins = _element(source, "incrementalMFD", minMag=f"{mfd.min_magnitude:.10g}", binWidth=f"{mfd.bin_width:.10g}")
    _element(bins, "occurRates", " ".join(f"{rate:.10e}" for rate in np.asarray(mfd.rates, dtype=float)))


def write_source_model(path, segments: list[dict], name: str, tectonic_region: str = "Active Shallow Crust") -> int:
    """Write ``segments`` (dicts: id, name, trace (n, 2) lon/lat, dip, rake, upper_depth and lower_depth in m,
    ``mfd`` a magnitude-frequency distribution or None, optional ``scaling_relation``) as NRML; segments
    without a distribution (no stick-slip) are left out. Returns how many sources were written."""
    root = _root()
    model = _element(root, "sourceModel", name=name)
    group = _element(model, "sourceGroup", name="faultslip predictions", tectonicRegion=tectonic_region)
    written = 0
    for segment in segments:
        mfd = segment.get("mfd")
        if mfd is None:
            continue
        relation = segment.get("scaling_relation", "WC1994")
        if relation not in ENGINE_SCALING_RELATIONS:
            raise InputError(f"the engine's scaling relation must be one of {', '.join(ENGINE_SCALING_RELATIONS)}, "
                             f"got {relation!r}")
        source = _element(group, "simpleFaultSource", id=str(segment["id"]), name=str(segment["name"]),
                          tectonicRegion=tectonic_region)
        geometry = _element(source, "simpleFaultGeometry")
        line = ET.SubElement(geometry, f"{{{GML_NAMESPACE}}}LineString")
        ET.SubElement(line, f"{{{GML_NAMESPACE}}}posList").text = " ".join(
            f"{lon:.5f} {lat:.5f}" for lon, lat in np.asarray(segment["trace"], dtype=float))
        _element(geometry, "dip", f"{segment['dip']:g}")
        _element(geometry, "upperSeismoDepth", f"{segment['upper_depth'] / 1e3:g}")
        _element(geometry, "lowerSeismoDepth", f"{segment['lower_depth'] / 1e3:g}")
        _element(source, "magScaleRel", relation)
        _element(source, "ruptAspectRatio", "2.0")
        _mfd_element(source, mfd)
        _element(source, "rake", f"{segment['rake']:g}")
        written += 1
    if not written:
        raise InputError("no segment has stick-slip (a magnitude and a recurrence): nothing to write as NRML")
    _write(root, path)
    return written


def occurrence_probabilities(probability: float) -> str:
    """``"P0 P1"``, the probabilities of no rupture and of one in the investigation time, as ``probs_occur``
    writes them: the larger is written to 17 significant digits and the smaller is 1 minus it, which is exact
    (Sterbenz), so that the two sum to 1 exactly as the engine requires, and P1 is ``probability`` to 1 ulp."""
    if not 0.0 <= probability <= 1.0:
        raise InputError(f"an occurrence probability must lie from 0 to 1, got {probability!r}")
    if probability <= 0.5:
        none = float(f"{1.0 - probability:.17g}")
        one = 1.0 - none
    else:
        one = float(f"{probability:.17g}")
        none = 1.0 - one
    return f"{none!r} {one!r}"


def write_nonparametric_model(path, ruptures: list[dict], name: str, investigation_time: float,
                              tectonic_region: str = "Active Shallow Crust") -> int:
    """Write ``ruptures`` as ``nonParametricSeismicSource`` elements, one rupture each: a ``simpleFaultRupture``
    of the whole segment (dicts: id, name, trace (n, 2) lon/lat, dip, rake, upper_depth and lower_depth in m,
    magnitude, and ``probability`` of one rupture within ``investigation_time`` years). The hypocentre is at
    the trace's middle vertex, half-way down. Returns how many sources were written."""
    if not (math.isfinite(investigation_time) and investigation_time > 0):
        raise InputError(f"the investigation time must be a positive number of years, got {investigation_time!r}")
    root = _root()
    model = _element(root, "sourceModel", name=name, investigation_time=repr(float(investigation_time)))
    group = _element(model, "sourceGroup", name="faultslip time-dependent", tectonicRegion=tectonic_region)
    for rupture in ruptures:
        source = _element(group, "nonParametricSeismicSource", id=str(rupture["id"]), name=str(rupture["name"]),
                          tectonicRegion=tectonic_region)
        node = _element(source, "simpleFaultRupture", probs_occur=occurrence_probabilities(rupture["probability"]))
        _element(node, "magnitude", f"{rupture['magnitude']:.10g}")
        _element(node, "rake", f"{rupture['rake']:g}")
        trace = np.asarray(rupture["trace"], dtype=float)
        lon, lat = trace[len(trace) // 2]
        _element(node, "hypocenter", lon=f"{lon:.5f}", lat=f"{lat:.5f}",
                 depth=f"{(rupture['upper_depth'] + rupture['lower_depth']) / 2e3:g}")
        geometry = _element(node, "simpleFaultGeometry")
        line = ET.SubElement(geometry, f"{{{GML_NAMESPACE}}}LineString")
        ET.SubElement(line, f"{{{GML_NAMESPACE}}}posList").text = " ".join(f"{x:.5f} {y:.5f}" for x, y in trace)
        _element(geometry, "dip", f"{rupture['dip']:g}")
        _element(geometry, "upperSeismoDepth", f"{rupture['upper_depth'] / 1e3:g}")
        _element(geometry, "lowerSeismoDepth", f"{rupture['lower_depth'] / 1e3:g}")
    if not ruptures:
        raise InputError("no segment has a rupture to write as a time-dependent source")
    _write(root, path)
    return len(ruptures)


def section_profiles(trace, dip: float, upper_depth: float, lower_depth: float) -> list:
    """A section's ``kiteSurface`` profiles: at each trace vertex, (lon, lat, depth km) at the upper seismogenic
    depth and, (lower - upper) / tan(dip) further down dip (to the right of the strike, Aki & Richards), at the
    lower one."""
    trace = np.asarray(trace, float)
    reach = 0.0 if dip >= 90.0 else (lower_depth - upper_depth) / math.tan(math.radians(dip))
    profiles = []
    for i, (lon, lat) in enumerate(trace):
        a, b = (trace[i], trace[i + 1]) if i + 1 < len(trace) else (trace[i - 1], trace[i])
        bottom = destination(lon, lat, azimuth(a, b) + 90.0, reach) if reach else (lon, lat)
        profiles.append(((lon, lat, upper_depth / 1e3), (*bottom, lower_depth / 1e3)))
    return profiles


def write_sections(path, sections: list[dict], name: str = "faultslip fault sections") -> int:
    """Write ``sections`` (dicts: trace (n, 2) lon/lat, dip, upper_depth and lower_depth in m; optional name) as
    an NRML ``geometryModel`` of ``kiteSurface`` sections with ids 0, 1, ... (the indexes a
    ``multiPlanesRupture`` names). Returns how many were written."""
    if not sections:
        raise InputError("a fault system needs at least one section to write")
    root = _root()
    model = _element(root, "geometryModel", name=name)
    for index, section in enumerate(sections):
        node = _element(model, "section", id=str(index), name=str(section.get("name", index)))
        surface = _element(node, "kiteSurface")
        for top, bottom in section_profiles(section["trace"], section["dip"], section["upper_depth"],
                                            section["lower_depth"]):
            profile = _element(surface, "profile")
            line = ET.SubElement(profile, f"{{{GML_NAMESPACE}}}LineString")
            ET.SubElement(line, f"{{{GML_NAMESPACE}}}posList").text = " ".join(f"{v:.6f}" for v in (*top, *bottom))
    _write(root, path)
    return len(sections)


def write_multi_fault_model(path, ruptures: list[dict], name: str, background: dict | None = None,
                            tectonic_region: str = "Active Shallow Crust") -> int:
    """Write a fault system's ruptures (dicts: magnitude, rake, sections (indexes into :func:`write_sections`'s
    file), rate in 1/yr) as one ``multiFaultSource``, each rupture's rate as its one-year probabilities
    "exp(-rate) 1-exp(-rate)" (the job needs ``infer_occur_rates = true``); ruptures without a rate are left
    out. ``background`` (dict: polygon (n, 2) lon/lat, upper_depth and lower_depth in m, ``mfd`` a truncated
    Gutenberg-Richter distribution, rake) adds an ``areaSource``. Returns how many ruptures were written."""
    root = _root()
    model = _element(root, "sourceModel", name=name, investigation_time="1.0")
    group = _element(model, "sourceGroup", name="faultslip fault system", tectonicRegion=tectonic_region)
    source = _element(group, "multiFaultSource", id="fault_system", name=name)
    written = 0
    for rupture in ruptures:
        rate = float(rupture["rate"])
        if not (math.isfinite(rate) and rate > 0):
            continue
        node = _element(source, "multiPlanesRupture", probs_occur=occurrence_probabilities(-math.expm1(-rate)))
        _element(node, "magnitude", f"{rupture['magnitude']:.10g}")
        _element(node, "sectionIndexes", indexes=",".join(str(int(i)) for i in rupture["sections"]))
        _element(node, "rake", f"{rupture['rake']:g}")
        written += 1
    if not written:
        raise InputError("no rupture of the fault system has a rate: nothing to write as a multiFaultSource")
    if background is not None and background["mfd"] is not None:
        area = _element(group, "areaSource", id="background", name=f"{name}: background", tectonicRegion=tectonic_region)
        geometry = _element(area, "areaGeometry")
        polygon = ET.SubElement(geometry, f"{{{GML_NAMESPACE}}}Polygon")
        ring = ET.SubElement(ET.SubElement(polygon, f"{{{GML_NAMESPACE}}}exterior"), f"{{{GML_NAMESPACE}}}LinearRing")
        ET.SubElement(ring, f"{{{GML_NAMESPACE}}}posList").text = " ".join(
            f"{lon:.5f} {lat:.5f}" for lon, lat in np.asarray(background["polygon"], float))
        _element(geometry, "upperSeismoDepth", f"{background['upper_depth'] / 1e3:g}")
        _element(geometry, "lowerSeismoDepth", f"{background['lower_depth'] / 1e3:g}")
        _element(area, "magScaleRel", "WC1994")
        _element(area, "ruptAspectRatio", "1.5")
        _mfd_element(area, background["mfd"])
        planes = _element(area, "nodalPlaneDist")
        _element(planes, "nodalPlane", probability="1.0", strike="0.0", dip="90.0", rake=f"{background['rake']:g}")
        depths = _element(area, "hypoDepthDist")
        _element(depths, "hypoDepth", probability="1.0",
                 depth=f"{(background['upper_depth'] + background['lower_depth']) / 2e3:g}")
    _write(root, path)
    return written


def write_logic_tree(path, branches: list[tuple[str, str, float]]) -> None:
    """A source-model logic tree: ``branches`` of (branch id, source-model file name relative to ``path``,
    weight); the weights must sum to 1 (to 1e-9: the engine checks it)."""
    weights = [weight for _, _, weight in branches]
    if not branches or not all(math.isfinite(w) and w > 0 for w in weights) or abs(sum(weights) - 1.0) > 1e-9:
        raise InputError(f"logic-tree weights must be positive and sum to 1, got {weights}")
    root = _root()
    tree = _element(root, "logicTree", logicTreeID="faultslip")
    branch_set = _element(tree, "logicTreeBranchSet", uncertaintyType="sourceModel", branchSetID="scaling_relations")
    for branch_id, file_name, weight in branches:
        branch = _element(branch_set, "logicTreeBranch", branchID=branch_id)
        _element(branch, "uncertaintyModel", file_name)
        _element(branch, "uncertaintyWeight", repr(float(weight)))
    _write(root, path)
