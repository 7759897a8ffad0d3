r"""Fault-system rupture sets: ruptures that jump between sections, with rates that keep every section's slip rate.

A map's faults become **sections** (each mapped segment, or its subsections of about ``subsection_length``
along strike, as UCERF3 cuts faults; Field et al. 2014, BSSA 104(3), 1122-1180). The **ruptures** are the
sequences of neighbouring sections the stated rules allow (Milner et al. 2013, UCERF3 appendix T):

- two sections of one fault are neighbours end to end; two faults are joined, once, at their closest
  sections, if those are no further apart than ``max_jump``;
- a rupture takes each fault once, as one run of its sections, and turns by no more than
  ``max_azimuth_change`` from one section's direction of travel to the next one's;
- it has from ``min_sections`` to ``max_sections`` sections.

**Magnitudes and slips** (N m, m): on the ``faultslip`` branch a rupture slips each section by faultslip's
slip per event for that section's fault, so M0 = G sum_s A_s D_s; on the empirical branches (W&C 1994
Mw(RA), Leonard 2010 Mw(A)) the rupture's area gives Mw and a uniform slip M0 / (G A).

**Rates** r_k >= 0 (1/yr) solve, by scipy's non-negative least squares (Lawson & Hanson 1974),

.. math:: \sum_k D_{sk} r_k = (1 - f_{a,s})(1 - f_b) V_s \quad\text{for every section } s,

the slip-rate budget after the aseismic (non-mainshock) fraction f_a and the background share f_b, held to
1e-6 relative, while the system's incremental magnitude-frequency distribution N_j = sum_{k in bin j} r_k
follows the stated shape up to a free level c (each bin's misfit relative to its target):

- ``gr``: Gutenberg-Richter, N_j proportional to 10^(-b m_j);
- ``characteristic``: each fault's faultslip-predicted event (its Mw, at its moment rate) in its bin.

The slip rows are weighted far above the shape rows, and the rates on the active set are then corrected
onto the slip constraints exactly (least norm), so the budget holds to round-off; a shape the slip rates
cannot follow shows as the misfit, which the result reports. Many rate sets fit equally well (there are more
ruptures than sections and bins), and NNLS alone returns one vertex of them, chosen by round-off: a relative
change of 1e-14 in the slips moved the bundled system's ruptures with a rate from 27 to between 28 and 35. All of
them give the same fitted values (the least-squares objective is strictly convex in them), and among them the
least-norm rates are unique and move with the inputs continuously: they spread the budget over every rupture that
can carry it. :func:`least_norm_rates` finds them from NNLS's fitted values by a generalised Newton method on the
dual (Mangasarian 2004) inside a proximal-point loop; its unknowns are one per row, so its cost grows with the
ruptures only linearly. Where the rates that fit are a single point, that point is NNLS's. Where the budget and the
shape conflict, the least-squares rates miss the budget however heavily it is weighted, and the rates are the
nearest that release it (:func:`project_onto_budget`). If the Newton method fails, the result keeps NNLS's rates
and its notes say why and that they are one of many. The background's share of the moment rate goes to an area
source around the faults (a truncated Gutenberg-Richter distribution).
"""

from __future__ import annotations

import hashlib
import math
from dataclasses import dataclass, field

import numpy as np

from faultslip.errors import InputError, SolverError
from faultslip.fault import empirical, mfd as mfds
from faultslip.fault.scaling import moment_magnitude
from faultslip.io import budget, machine
from faultslip.io.geo import EARTH_RADIUS, azimuth, densify, destination, great_circle, trace_length
from faultslip.units import JULIAN_YEAR, to_si
from faultslip.datasets import ToXarray

#: the target shapes of the system's magnitude-frequency distribution
SHAPES = ("gr", "characteristic")
#: the magnitude relations a rupture set takes (as the per-segment branches; studies.hazard.RELATIONS)
RELATIONS = ("faultslip", "WC1994", "Leonard2010")
#: more ruptures than this is refused: a rule set that loose needs tighter rules, not more memory
MAX_RUPTURES = 200_000
#: Copies of the rate problem's dense arrays (sections and bins by ruptures, 8 B each) held at once while the rates
#: are solved: the slips, the weighted NNLS matrix and NNLS's own copy, the rescaled rows and their projection
#: (tracemalloc's peak over the magnitudes and the solve of the bundled system cut into 1,297 and 4,632 ruptures:
#: 5.6 and 6.2 copies; tests/capabilities/hazard/test_rupture_sets.py)
RATE_MATRIX_COPIES = 8
#: Rows besides the sections' that bound the shape's magnitude bins (0.1 wide over 4 magnitude units)
RATE_BIN_ROWS = 41
#: The rate solve's cost model (:func:`rate_estimate`), fitted by ``benchmarks/rupture_rate_cost.py`` in the machine
#: state of the "families" cost group (:mod:`faultslip.io.machine`): CPU seconds a branch per row squared per
#: rupture (NNLS's active-set loop: each row's columns change a few times, each change a least-squares solve of
#: rows x ruptures), a branch's overhead (the 95th percentile of drawn rule sets' solves: a proximal loop or BVLS's
#: check), and the enumeration and magnitudes' seconds per rupture
RATE_SOLVE_SECONDS = {"rate_seconds": 2.547e-9, "overhead_seconds": 0.1838, "enumeration_seconds": 7.924e-5}
#: the slip-rate budget's relative tolerance
BUDGET_TOLERANCE = 1e-6
#: The least-norm step's tolerance: each row of matrix @ x = fitted (scaled to a largest entry of 1) is met to this
#: relative to the largest fitted value; the budget is then met to round-off by the step onto it
LEAST_NORM_TOLERANCE = 1e-10
#: The weights on the slip rows against the shape rows, tried in turn
WEIGHTS = (1e3, 1e5, 1e7, 1e9)
#: Below the heaviest weight, least-squares rates this far off the budget (relative) wait for a heavier weight; at
#: or below it they are moved onto the budget (:func:`project_onto_budget`)
PROJECTION_LIMIT = 1e-4
#: The least-norm step's proximal term on the dual, relative to its Hessian's scale: the dual is then strongly
#: convex and its minimum attained, also where the rates that fit are one point (SHERIFS's Example); the rows are
#: met to this times the multipliers, and the step onto the budget then closes the slip rows
LEAST_NORM_RIDGE = 1e-12
#: Where the rows cannot be met to the tolerance (the rates that fit are nearly one point: the dual's minimum runs
#: off), the first proximal minimum (the ridge's least-norm rates, unique) is taken if it meets them to this
REGULARISED_TOLERANCE = 1e-4
#: Newton steps the least-norm step may take (the bundled system, cut into 356 to 4,632 ruptures, solves 15 to 18
#: Newton systems, damped retries included)
LEAST_NORM_STEPS = 300
#: How far (log10) a bin of solved rates may lie off the fitted line for them to be called Gutenberg-Richter (12 %).
GR_LOG_TOLERANCE = 0.05


@dataclass(frozen=True)
class Rules:
    """What makes a rupture: jump, turn and size (SI: m, degrees)."""

    max_jump: float = 5e3
    max_azimuth_change: float = 60.0
    min_sections: int = 1
    max_sections: int | None = None
    subsection_length: float | None = None
    shape: str = "gr"
    b_value: float = 1.0
    aseismic_fraction: float | dict = 0.0  # one number, or segment id -> fraction
    background_share: float = 0.0
    background_magnitudes: tuple = (5.0, 6.5)
    weight: float = 0.5  # the system branches' share of the logic tree
    #: the multi-fault ruptures, stated (fault ids in order; SHERIFS's rupture sets): None lets the jump and turn
    #: rules find them
    ruptures: tuple | None = None

    def as_dict(self) -> dict:
        return {"max_jump": {"value": self.max_jump, "units": "m"}, "max_azimuth_change": self.max_azimuth_change,
                "min_sections": self.min_sections, "max_sections": self.max_sections,
                "subsection_length": None if self.subsection_length is None else
                {"value": self.subsection_length, "units": "m"},
                "shape": self.shape, "b_value": self.b_value, "aseismic_fraction": self.aseismic_fraction,
                "background_share": self.background_share, "background_magnitudes": list(self.background_magnitudes),
                "weight": self.weight,
                "ruptures": None if self.ruptures is None else [list(rupture) for rupture in self.ruptures]}


#: the keys of a map's [rupture_set] table
RULE_KEYS = ("max_jump", "max_azimuth_change", "min_sections", "max_sections", "subsection_length", "mfd", "b_value",
             "aseismic_fraction", "background_share", "background_min_magnitude", "background_max_magnitude",
             "weight", "ruptures")


def parse_rules(table: dict, where: str, segment_ids=()) -> Rules:
    """A map's ``[rupture_set]`` table as :class:`Rules`, each bad value refused in one sentence."""
    def whole(key, default, low):
        value = table.get(key, default)
        if value is None:
            return None
        if not isinstance(value, int) or isinstance(value, bool) or value < low:
            raise InputError(f"{where}: {key} must be a whole number of at least {low}, got {value!r}")
        return value

    def fraction(value, what, top=1.0):
        if not isinstance(value, (int, float)) or isinstance(value, bool) or not (0.0 <= value < top):
            raise InputError(f"{where}: {what} must be a number from 0 to below {top:g}, got {value!r}")
        return float(value)

    max_jump = to_si(table.get("max_jump", "5 km"), "length", f"{where} max_jump")
    if not (math.isfinite(max_jump) and max_jump >= 0):
        raise InputError(f"{where}: max_jump must be a distance of 0 or more, got {table.get('max_jump')!r}")
    turn = table.get("max_azimuth_change", 60.0)
    if not isinstance(turn, (int, float)) or isinstance(turn, bool) or not 0 <= turn <= 180:
        raise InputError(f"{where}: max_azimuth_change must be degrees from 0 to 180, got {turn!r}")
    low, high = whole("min_sections", 1, 1), whole("max_sections", None, 1)
    if high is not None and high < low:
        raise InputError(f"{where}: max_sections ({high}) is below min_sections ({low})")
    length = None
    if "subsection_length" in table:
        length = to_si(table["subsection_length"], "length", f"{where} subsection_length")
        if not (math.isfinite(length) and length >= 1e3):
            raise InputError(f"{where}: subsection_length must be at least 1 km, got {table['subsection_length']!r}")
    shape = table.get("mfd", "gr")
    if shape not in SHAPES:
        raise InputError(f"{where}: mfd must be one of {', '.join(SHAPES)}, got {shape!r}")
    b_value = table.get("b_value", 1.0)
    if not isinstance(b_value, (int, float)) or isinstance(b_value, bool) or not 0.3 <= b_value <= 2.5:
        raise InputError(f"{where}: b_value must be a number from 0.3 to 2.5, got {b_value!r}")
    aseismic = table.get("aseismic_fraction", 0.0)
    if isinstance(aseismic, dict):
        unknown = sorted(set(aseismic) - set(map(str, segment_ids)))
        if unknown:
            raise InputError(f"{where}: aseismic_fraction names segment {unknown[0]!r}, which the map does not have")
        aseismic = {str(key): fraction(value, f"aseismic_fraction of {key}") for key, value in aseismic.items()}
    else:
        aseismic = fraction(aseismic, "aseismic_fraction")
    background = fraction(table.get("background_share", 0.0), "background_share")
    magnitudes = (table.get("background_min_magnitude", 5.0), table.get("background_max_magnitude", 6.5))
    if not all(isinstance(m, (int, float)) and not isinstance(m, bool) and 3 <= m <= 9 for m in magnitudes) or \
            magnitudes[1] <= magnitudes[0]:
        raise InputError(f"{where}: the background's magnitudes must run from 3 to 9, minimum below maximum, "
                         f"got {magnitudes[0]!r} to {magnitudes[1]!r}")
    weight = table.get("weight", 0.5)
    if not isinstance(weight, (int, float)) or isinstance(weight, bool) or not 0 < weight <= 1:
        raise InputError(f"{where}: weight (the rupture set's share of the logic tree) must be in (0, 1], got {weight!r}")
    listed = table.get("ruptures")
    if listed is not None:
        known = set(map(str, segment_ids))
        if not isinstance(listed, list) or len(listed) > MAX_RUPTURES:
            raise InputError(f"{where}: ruptures must be a list of ruptures, each a list of fault ids, got {listed!r}")
        for rupture in listed:
            if not (isinstance(rupture, list) and len(rupture) >= 2 and all(isinstance(n, str) for n in rupture)
                    and len(set(rupture)) == len(rupture)):
                raise InputError(f"{where}: each rupture of ruptures lists two or more different fault ids, "
                                 f"got {rupture!r}")
            unknown = [name for name in rupture if name not in known]
            if unknown:
                raise InputError(f"{where}: a rupture names fault {unknown[0]!r}, which the map does not have "
                                 f"({', '.join(sorted(known))})")
        listed = tuple(tuple(rupture) for rupture in listed)
    return Rules(max_jump, float(turn), low, high, length, shape, float(b_value), aseismic, background,
                 (float(magnitudes[0]), float(magnitudes[1])), float(weight), listed)


@dataclass
class Sections:
    """A fault system's sections (SI), each belonging to one mapped fault (``fault``, an index)."""

    ids: list
    names: list
    fault: np.ndarray
    fault_ids: list
    traces: list
    dip: np.ndarray
    rake: np.ndarray
    upper_depth: np.ndarray
    lower_depth: np.ndarray
    length: np.ndarray
    slip_rate: np.ndarray  # m/s
    slip_per_event: np.ndarray  # m, faultslip's for the section's fault
    fault_magnitude: np.ndarray  # faultslip's Mw for the whole fault
    fault_moment_rate: np.ndarray  # N m/yr, the whole fault's
    aseismic: np.ndarray

    @property
    def count(self) -> int:
        return len(self.ids)

    @property
    def width(self) -> np.ndarray:
        """Down-dip width (lower - upper) / sin(dip) (m)."""
        return (self.lower_depth - self.upper_depth) / np.sin(np.radians(self.dip))

    @property
    def area(self) -> np.ndarray:
        return self.length * self.width


def _cumulative_distance(points: np.ndarray) -> np.ndarray:
    """Great-circle distance (m) along ``points`` (lon, lat degrees) from the first, at each."""
    steps = great_circle(points[:-1, 0], points[:-1, 1], points[1:, 0], points[1:, 1])
    return np.concatenate([[0.0], np.cumsum(steps)])


def split_trace(trace, pieces: int) -> list:
    """``trace`` cut into ``pieces`` of equal length along it (great circles; each keeps the vertices inside it
    that are more than 1 km from its ends)."""
    trace = np.asarray(trace, float)
    if pieces == 1:
        return [trace]
    points = densify(trace, 100.0)
    along = _cumulative_distance(points)
    vertex_along = _cumulative_distance(trace)  # the densified points lie on the great circles between vertices
    cuts = np.linspace(0.0, along[-1], pieces + 1)
    cut_points = np.column_stack([np.interp(cuts, along, points[:, 0]), np.interp(cuts, along, points[:, 1])])
    out = []
    for i in range(pieces):
        # a vertex within 1 km of a cut would leave a sliver the engine's surfaces cannot mesh: the cut stands for it
        inside = trace[(vertex_along > cuts[i] + 1e3) & (vertex_along < cuts[i + 1] - 1e3)]
        out.append(np.vstack([cut_points[i], *inside, cut_points[i + 1]]) if len(inside) else cut_points[i:i + 2])
    return out


def fault_sections(spec, dataset, rules: Rules) -> Sections:
    """The map's faults as sections (or subsections of ``rules.subsection_length``), with faultslip's slip per
    event and event for each fault, from the map's predictions ``dataset``; with ``dataset`` None, their geometry
    alone (every prediction NaN: what the map's estimate enumerates its ruptures from, before any work)."""
    table = spec.segments
    if table is None:
        raise InputError("a rupture set needs fault segments ([segments]), not a raster map")
    geometry = table.geometry or {}
    count = len(table.ids)
    dip = np.asarray(geometry.get("dip", np.full(count, 90.0)), float)
    rake = np.asarray(geometry.get("rake", np.full(count, 180.0)), float)
    upper = np.asarray(geometry.get("upper_depth", np.zeros(count)), float)
    unknown = np.full(count, math.nan)
    slip, magnitude, recurrence, moment = (
        (unknown,) * 4 if dataset is None else
        (dataset[name].values for name in ("slip_per_event", "moment_magnitude", "recurrence_period",
                                           "seismic_moment")))
    rows = {key: [] for key in ("ids", "names", "fault", "traces", "dip", "rake", "upper", "lower", "length", "rate",
                                "slip", "magnitude", "moment_rate", "aseismic")}
    for i, trace in enumerate(table.traces):
        length = trace_length(trace)
        pieces = 1 if rules.subsection_length is None else max(1, int(round(length / rules.subsection_length)))
        fraction = (rules.aseismic_fraction.get(str(table.ids[i]), 0.0) if isinstance(rules.aseismic_fraction, dict)
                    else rules.aseismic_fraction)
        stick_slip = math.isfinite(slip[i]) and math.isfinite(recurrence[i]) and recurrence[i] > 0
        for j, piece in enumerate(split_trace(trace, pieces)):
            rows["ids"].append(str(table.ids[i]) if pieces == 1 else f"{table.ids[i]}.{j + 1}")
            rows["names"].append(str(table.names[i]) if pieces == 1 else f"{table.names[i]} {j + 1}/{pieces}")
            rows["fault"].append(i)
            rows["traces"].append(piece)
            rows["length"].append(trace_length(piece))
            for key, value in (("dip", dip[i]), ("rake", rake[i]), ("upper", upper[i]),
                               ("lower", upper[i] + table.seismogenic_depth[i]), ("rate", table.slip_rate[i]),
                               ("slip", slip[i] if stick_slip else math.nan),
                               ("magnitude", magnitude[i] if stick_slip else math.nan),
                               ("moment_rate", moment[i] / recurrence[i] * JULIAN_YEAR if stick_slip else math.nan),
                               ("aseismic", fraction)):
                rows[key].append(float(value))
    array = lambda key: np.array(rows[key], float)  # noqa: E731
    return Sections(rows["ids"], rows["names"], np.array(rows["fault"]), [str(x) for x in table.ids], rows["traces"],
                    array("dip"), array("rake"), array("upper"), array("lower"), array("length"), array("rate"),
                    array("slip"), array("magnitude"), array("moment_rate"), array("aseismic"))


def _turn(a: float, b: float) -> float:
    return abs((a - b + 180.0) % 360.0 - 180.0)


def _distance(a, b) -> float:
    return float(_cumulative_distance(np.array([a, b], float))[-1])


def connections(sections: Sections, rules: Rules) -> dict:
    """section -> {neighbour: (the end of the section a rupture leaves by, the end of the neighbour it enters by)},
    ends as 0 (first vertex) and 1 (last)."""
    links = {s: {} for s in range(sections.count)}
    ends = [(np.asarray(t[0]), np.asarray(t[-1])) for t in sections.traces]
    for s in range(sections.count - 1):  # subsections of one fault, end to end
        if sections.fault[s] == sections.fault[s + 1]:
            links[s][s + 1], links[s + 1][s] = (1, 0), (0, 1)
    faults = np.unique(sections.fault)
    dense = [densify(t, 500.0) for t in sections.traces]
    for i, a in enumerate(faults):
        for b in faults[i + 1:]:
            best = (math.inf, None, None)
            for s in np.flatnonzero(sections.fault == a):
                for t in np.flatnonzero(sections.fault == b):
                    gap = _closest(dense[s], dense[t])
                    if gap < best[0]:
                        best = (gap, int(s), int(t))
            gap, s, t = best
            if s is not None and gap <= rules.max_jump:
                # a rupture leaves one section, and enters the other, by the end nearer the other
                near_s, near_t = _near_end(ends[s], dense[t]), _near_end(ends[t], dense[s])
                links[s][t], links[t][s] = (near_s, near_t), (near_t, near_s)
    return links


def _closest(a: np.ndarray, b: np.ndarray) -> float:
    from scipy.spatial.distance import cdist  # heavy: imported where used

    va = _vectors(a)
    vb = _vectors(b)
    chord = cdist(va, vb).min()
    return float(2 * EARTH_RADIUS * math.asin(min(chord / 2, 1.0)))


def _vectors(points):
    lon, lat = np.radians(points[:, 0]), np.radians(points[:, 1])
    return np.column_stack([np.cos(lat) * np.cos(lon), np.cos(lat) * np.sin(lon), np.sin(lat)])


def _near_end(ends, other: np.ndarray) -> int:
    """0 if the section's first vertex is nearer ``other`` than its last, else 1."""
    return int(_closest(np.array([ends[1]]), other) < _closest(np.array([ends[0]]), other))


def stated_ruptures(sections: Sections, rules: Rules) -> list[tuple]:
    """The ruptures of a stated list (SHERIFS's rupture sets): on each fault, every run of its sections from
    ``min_sections`` to ``max_sections`` long (the whole fault, without subsections), and each stated multi-fault
    rupture, its faults' sections end to end in the order stated. The jump and turn rules do not apply."""
    most = rules.max_sections or sections.count
    by_fault = {fault_id: [s for s in range(sections.count) if sections.fault[s] == index]
                for index, fault_id in enumerate(sections.fault_ids)}
    found = set()
    for runs in by_fault.values():
        for start in range(len(runs)):
            for stop in range(start + rules.min_sections, min(len(runs), start + most) + 1):
                path = tuple(runs[start:stop])
                found.add(min(path, path[::-1]))
    for rupture in rules.ruptures:
        path = tuple(s for fault_id in rupture for s in by_fault[fault_id])
        found.add(min(path, path[::-1]))
    return sorted(found, key=lambda p: (len(p), p))


#: The last enumeration, by a digest of what it reads: a map that checks its budget enumerates its ruptures from
#: the sections' geometry (:func:`rupture_set_estimate`), and its run again from the same sections with their
#: predictions (4.4 s twice at 50,463 ruptures); the geometry and the rules alone decide them.
_LAST_ENUMERATION: dict = {}


def _enumeration_key(sections: Sections, rules: Rules) -> str:
    digest = hashlib.sha256(repr(rules).encode())
    digest.update(repr((list(sections.ids), list(sections.fault_ids))).encode())
    digest.update(np.ascontiguousarray(sections.fault, dtype=np.int64).tobytes())
    for trace in sections.traces:
        digest.update(np.ascontiguousarray(trace, dtype=float).tobytes())
        digest.update(b"|")
    return digest.hexdigest()


def enumerate_ruptures(sections: Sections, rules: Rules) -> list[tuple]:
    """Every rupture the rules allow, as a tuple of section indices in order along the rupture (each once); where
    the rules state the multi-fault ruptures, those (:func:`stated_ruptures`). The same sections' geometry and
    rules as the last call give its ruptures again without enumerating them (a map's estimate, then its run)."""
    key = _enumeration_key(sections, rules)
    if key not in _LAST_ENUMERATION:
        _LAST_ENUMERATION.clear()
        _LAST_ENUMERATION[key] = tuple(_enumerated(sections, rules))
    return list(_LAST_ENUMERATION[key])


def _enumerated(sections: Sections, rules: Rules) -> list[tuple]:
    if rules.ruptures is not None:
        return stated_ruptures(sections, rules)
    links = connections(sections, rules)
    most = rules.max_sections or sections.count
    direction = {}  # (section, entry end) -> azimuth of travel through it

    def heading(s, entry):
        key = (s, entry)
        if key not in direction:
            trace = sections.traces[s]
            a, b = (trace[0], trace[-1]) if entry == 0 else (trace[-1], trace[0])
            direction[key] = azimuth(a, b)
        return direction[key]

    found = set()
    stack = []
    for s in range(sections.count):
        for entry in (0, 1):  # a rupture may run through its first section either way
            stack.append(((s,), entry, frozenset([sections.fault[s]])))
    while stack:
        path, entry, faults = stack.pop()
        if len(path) >= rules.min_sections:
            found.add(min(path, path[::-1]))
            if len(found) > MAX_RUPTURES:
                raise InputError(f"the rupture rules allow more than {MAX_RUPTURES:,} ruptures: lower max_jump, "
                                 "max_azimuth_change or max_sections, or lengthen subsection_length")
        if len(path) >= most:
            continue
        last = path[-1]
        for neighbour, (leaves, enters) in links[last].items():
            if leaves != 1 - entry or neighbour in path:
                continue  # a rupture leaves a section by the end it did not enter by
            if sections.fault[neighbour] != sections.fault[last] and sections.fault[neighbour] in faults:
                continue  # each fault once, as one run
            if _turn(heading(last, entry), heading(neighbour, enters)) > rules.max_azimuth_change:
                continue
            stack.append((path + (neighbour,), enters, faults | {sections.fault[neighbour]}))
    ruptures = sorted(found, key=lambda p: (len(p), p))
    if not ruptures:
        raise InputError(f"the rupture rules allow no rupture: no run of {rules.min_sections} or more sections is "
                         "joined within max_jump and max_azimuth_change")
    return ruptures


@dataclass
class RuptureSet(ToXarray):
    """A fault system's ruptures, their magnitudes, slips and solved rates on one relation's branch."""
    #: the units and dimensions of to_xarray() (faultslip.datasets.ToXarray)
    UNITS = {'magnitude': '1', 'rate': '1/yr', 'budget': 'm/yr', 'bins': '1', 'target': '1/yr', 'background_moment_rate': 'N m/yr', 'shear_modulus': 'Pa', 'bin_width': '1', 'slip': 'm'}
    DIMENSIONS = {'magnitude': 'rupture', 'rate': 'rupture', 'bins': 'bin', 'target': 'bin'}

    relation: str
    sections: Sections
    rules: Rules
    ruptures: list  # tuples of section indices
    magnitude: np.ndarray
    slip: np.ndarray  # (sections, ruptures) m
    rate: np.ndarray  # 1/yr
    budget: np.ndarray  # m/yr each section must release
    bins: np.ndarray  # bin centres of the target
    target: np.ndarray  # the target's rates (1/yr) at its solved level
    background_moment_rate: float  # N m/yr
    shear_modulus: float
    notes: list = field(default_factory=list)
    bin_width: float = 0.1  # of the target's bins (``bins`` holds the targeted ones: it may have gaps)

    @property
    def released(self) -> np.ndarray:
        """Slip rate each section releases (m/yr)."""
        return self.slip @ self.rate

    @property
    def budget_error(self) -> float:
        """The largest |released - budget| / budget over the sections with a budget."""
        has = self.budget > 0
        return float(np.max(np.abs(self.released[has] - self.budget[has]) / self.budget[has])) if has.any() else 0.0

    @property
    def participation(self) -> np.ndarray:
        """Each section's rate of ruptures it takes part in (1/yr)."""
        return (self.slip > 0).astype(float) @ self.rate

    def system_mfd(self) -> np.ndarray:
        """The solved rates summed into the target's bins (1/yr), each rupture in the bin of the full grid that
        holds its magnitude: ``bins`` lists the targeted bins only, so a bin between them that no rupture reaches is
        absent, and binning as though they were contiguous put the rates after such a gap one bin off."""
        grid = np.floor((self.magnitude - (self.bins[0] - self.bin_width / 2)) / self.bin_width + 1e-9)
        slot = np.searchsorted(np.round((self.bins - self.bins[0]) / self.bin_width).astype(int), grid.astype(int))
        slot = np.clip(slot, 0, self.bins.size - 1)
        inside = np.round((self.bins[slot] - self.bins[0]) / self.bin_width).astype(int) == grid.astype(int)
        return np.bincount(slot[inside], weights=self.rate[inside], minlength=self.bins.size)

    def b_value(self) -> float:
        """The solved distribution's b-value: the slope of log10 of its incremental rates, least squares over the
        targeted bins that have a rate (each rupture in its own bin of the full grid, :meth:`system_mfd`)."""
        rates = self.system_mfd()
        has = rates > 0
        if has.sum() < 2:
            return math.nan
        return float(-np.polyfit(self.bins[has], np.log10(rates[has]), 1)[0])

    def b_value_fit(self) -> dict:
        """How well one line holds the solved rates (issue 69: no b-value without its goodness of fit). The rates
        are expected values, not a sample, so the fit is judged by its residuals rather than a KS test:
        ``log_rate_rms`` and ``log_rate_max`` (log10 units) of the least-squares line over the bins with a rate, and
        ``b_over_cutoffs``, the least and greatest b of the same fit above each lower cutoff that leaves 3 bins or
        more (how much the choice of the smallest magnitude alone moves it). ``gutenberg_richter`` is whether the
        rates lie within 0.05 in log10 (12 %) of the line everywhere."""
        rates = self.system_mfd()
        has = rates > 0
        bins, logs = self.bins[has], np.log10(rates[has]) if has.any() else np.array([])
        if bins.size < 2:
            return {"b": math.nan, "bins": int(bins.size), "log_rate_rms": None, "log_rate_max": None,
                    "b_over_cutoffs": None, "gutenberg_richter": False}
        slope, intercept = np.polyfit(bins, logs, 1)
        residual = logs - (slope * bins + intercept)
        spread = [float(-np.polyfit(bins[k:], logs[k:], 1)[0]) for k in range(bins.size - 2)] or [float(-slope)]
        worst = float(np.max(np.abs(residual)))
        return {"b": float(-slope), "bins": int(bins.size), "log_rate_rms": float(np.sqrt(np.mean(residual ** 2))),
                "log_rate_max": worst, "b_over_cutoffs": [min(spread), max(spread)],
                "gutenberg_richter": worst <= GR_LOG_TOLERANCE}

    def shape_misfit(self) -> float:
        """RMS of (solved - target) / target over the target's bins (0 when the shape is followed exactly; 1 for
        a bin left empty)."""
        return float(np.sqrt(np.mean((self.system_mfd() / self.target - 1.0) ** 2)))

    def moment_rate(self) -> float:
        """The ruptures' moment rate (N m/yr)."""
        return float(np.sum(self.rate * mfds.moment(self.magnitude)))

    def summary(self) -> dict:
        used = self.rate > 0
        return {"relation": self.relation, "sections": self.sections.count, "ruptures": len(self.ruptures),
                "ruptures_with_rate": int(used.sum()),
                "multi_fault_ruptures_with_rate": int(sum(1 for k in np.flatnonzero(used)
                                                          if len({self.sections.fault[s] for s in self.ruptures[k]}) > 1)),
                "budget_error": self.budget_error, "b_value": self.b_value(), "b_value_fit": self.b_value_fit(),
                "target_b_value": self.rules.b_value
                if self.rules.shape == "gr" else None, "shape": self.rules.shape, "shape_misfit": self.shape_misfit(),
                "magnitude_range": [float(self.magnitude.min()), float(self.magnitude.max())],
                "moment_rate": {"value": self.moment_rate(), "units": "N m/yr"},
                "background_moment_rate": {"value": self.background_moment_rate, "units": "N m/yr"},
                "participation": [{"section": sid, "rate": {"value": float(rate), "units": "1/yr"}}
                                  for sid, rate in zip(self.sections.ids, self.participation)]}


def _binned(magnitude, rate, bins) -> np.ndarray:
    width = bins[1] - bins[0] if bins.size > 1 else 0.1
    index = np.clip(np.floor((magnitude - (bins[0] - width / 2)) / width + 1e-9).astype(int), 0, bins.size - 1)
    return np.bincount(index, weights=rate, minlength=bins.size)


def rupture_magnitudes(sections: Sections, ruptures: list, relation: str, shear_modulus: float,
                       stable_continental: bool = False) -> tuple[np.ndarray, np.ndarray]:
    """(Mw of each rupture, slip matrix (sections, ruptures) in m) on ``relation``'s branch (see the module)."""
    if relation not in RELATIONS:
        raise InputError(f"a rupture set's relation must be one of {', '.join(RELATIONS)}, got {relation!r}")
    area = sections.area
    magnitude = np.empty(len(ruptures))
    slip = np.zeros((sections.count, len(ruptures)))
    for k, members in enumerate(ruptures):
        members = list(members)
        total = float(area[members].sum())
        if relation == "faultslip":
            if not np.all(np.isfinite(sections.slip_per_event[members])):
                magnitude[k] = math.nan
                continue
            slip[members, k] = sections.slip_per_event[members]
            magnitude[k] = float(moment_magnitude(shear_modulus * float(np.sum(area[members] * slip[members, k]))))
            continue
        # the rupture's slip type is its largest section's
        slip_type = empirical.slip_type_from_rake(float(sections.rake[members][np.argmax(area[members])]))
        if relation == "WC1994":
            magnitude[k] = float(empirical.magnitude_from_area(total, slip_type)[0])
        else:
            magnitude[k] = float(empirical.leonard_magnitude_from_area(
                total, empirical.leonard_setting(slip_type, stable_continental)))
        slip[members, k] = float(mfds.moment(magnitude[k])) / (shear_modulus * total)
    return magnitude, slip


@dataclass(frozen=True)
class RateRows:
    """The rate problem's rows (:func:`rate_rows`): a rupture set's unknowns are the scaled rates of its
    ``columns`` (rate = scaled × ``scale``) and the shape's level c."""

    columns: np.ndarray  # the ruptures with a magnitude
    scale: np.ndarray  # per column: the rate that would release its most loaded section alone
    slip_rows: np.ndarray  # per section with a budget: its slip released over its budget (target 1)
    shape_rows: np.ndarray  # per targeted bin: the rate in it over the shape (target c)
    budget: np.ndarray  # per section, m a year
    bins: np.ndarray
    shape: np.ndarray
    targeted: np.ndarray

    def matrix(self, weight: float) -> tuple:
        """The NNLS system at ``weight`` on the slip rows: (matrix, right-hand side), c in the last column."""
        matrix = np.block([[weight * self.slip_rows, np.zeros((self.slip_rows.shape[0], 1))],
                           [self.shape_rows, -np.ones((self.shape_rows.shape[0], 1))]])
        return matrix, np.concatenate([weight * np.ones(self.slip_rows.shape[0]), np.zeros(self.shape_rows.shape[0])])


def rate_rows(sections: Sections, magnitude: np.ndarray, slip: np.ndarray, rules: Rules,
              bin_width: float = 0.1) -> RateRows:
    """The rows :func:`solve_rates` fits: every section's slip budget and the system's shape, bin by bin."""
    usable = np.isfinite(magnitude)
    budget = sections.slip_rate * JULIAN_YEAR * (1 - sections.aseismic) * (1 - rules.background_share)
    stuck = [sections.ids[s] for s in range(sections.count)
             if budget[s] > 0 and not np.any(slip[s, usable] > 0)]
    if stuck:
        raise InputError(f"section {stuck[0]} has a slip rate but no rupture to release it (it has no stick-slip on "
                         f"this branch, or min_sections is larger than any run through it)")
    columns = np.flatnonzero(usable)
    low = math.floor(magnitude[columns].min() / bin_width + 0.5) * bin_width
    high = math.floor(magnitude[columns].max() / bin_width + 0.5) * bin_width
    bins = np.round(np.arange(low, high + bin_width / 2, bin_width), 10)
    if rules.shape == "gr":
        shape = 10.0 ** (-rules.b_value * bins)
    else:  # each fault's faultslip event, at its moment rate, in its bin
        shape = np.zeros(bins.size)
        faults = sorted(set(sections.fault.tolist()))
        for f in faults:
            first = int(np.flatnonzero(sections.fault == f)[0])
            m, rate = sections.fault_magnitude[first], sections.fault_moment_rate[first]
            if math.isfinite(m) and math.isfinite(rate):
                shape += _binned(np.array([m]), np.array([rate / float(mfds.moment(m))]), bins)
    occupied = _binned(magnitude[columns], np.ones(columns.size), bins) > 0
    targeted = occupied & (shape > 0)  # a bin no rupture reaches, or the shape leaves empty, is not fitted
    if not targeted.any():
        raise InputError("the stated magnitude-frequency shape puts no rate where the ruptures' magnitudes are")
    has = budget > 0
    slip_rows = slip[np.ix_(has, columns)] / budget[has, None]  # each row's target is 1
    membership = np.zeros((bins.size, columns.size))
    index = np.clip(np.floor((magnitude[columns] - (bins[0] - bin_width / 2)) / bin_width + 1e-9).astype(int), 0,
                    bins.size - 1)
    membership[index, np.arange(columns.size)] = 1.0
    shape_rows = membership[targeted] / shape[targeted, None]
    # columns scaled so each rate is of order one: the rate that would release its smallest section alone
    scale = 1.0 / np.max(slip_rows, axis=0)
    return RateRows(columns, scale, slip_rows * scale, shape_rows * scale, budget, bins, shape, targeted)


def solve_rates(sections: Sections, ruptures: list, magnitude: np.ndarray, slip: np.ndarray, rules: Rules,
                relation: str, shear_modulus: float, bin_width: float = 0.1) -> RuptureSet:
    """Rates that release every section's slip-rate budget and follow the stated shape (see the module)."""
    rows = rate_rows(sections, magnitude, slip, rules, bin_width)
    columns, scale, slip_rows, budget = rows.columns, rows.scale, rows.slip_rows, rows.budget
    bins, shape, targeted = rows.bins, rows.shape, rows.targeted
    solution, failed, regularised, moved = None, None, None, 0.0
    for weight in WEIGHTS:
        matrix, rhs = rows.matrix(weight)
        x = _least_squares(matrix, rhs)
        # every minimiser gives the same fitted values (the objective is strictly convex in them): of those, the
        # least-norm rates, which are unique
        least, said = least_norm_rates(matrix, matrix @ x, x)
        failed, regularised = (said, None) if least is None else (None, said)
        if least is None:
            least = x
        off = float(np.max(np.abs(slip_rows @ least[:-1] - 1.0)))
        if off > PROJECTION_LIMIT and weight != WEIGHTS[-1]:
            continue  # the budget and the shape conflict: a heavier weight on the budget first
        rates = least[:-1]
        if off > BUDGET_TOLERANCE / 10:  # onto the budget: the nearest rates that release it
            rates, why = project_onto_budget(rates, slip_rows)
            if rates is None:
                failed = why
                continue
            moved = max(moved, off)
        scaled = _onto_budget(rates, slip_rows)
        if scaled is not None:
            solution, level = scaled, least[-1]
            break
    if solution is None:
        raise SolverError(f"the rupture rates ({relation}): scipy's NNLS found no non-negative rates that release "
                          f"every section's slip rate to {BUDGET_TOLERANCE:g}; loosen the rules (more ruptures) or "
                          "give mfd = \"gr\" a smaller b_value")
    rate = np.zeros(len(ruptures))
    rate[columns] = solution * scale
    rate[rate < 1e-12 * rate.max()] = 0.0  # round-off of the active-set solve, not a rupture's rate
    if level <= 0:  # the shape rows are fitted by a zero level only if the slip rows left no room: report it as is
        level = float(np.sum(_binned(magnitude, rate, bins)[targeted] / shape[targeted]) / targeted.sum())
    target = np.where(targeted, level * shape, np.nan)
    moment_budget = float(np.sum(shear_modulus * sections.area * sections.slip_rate * JULIAN_YEAR *
                                 (1 - sections.aseismic)))
    result = RuptureSet(relation, sections, rules, ruptures, magnitude, slip, rate, budget, bins[targeted],
                        target[targeted], rules.background_share * moment_budget, shear_modulus, bin_width=bin_width)
    if failed is not None:
        result.notes.append(f"the rates ({relation}) are NNLS's, one of many rate sets that fit equally well, chosen "
                            f"by round-off: the least-norm step failed ({failed}); tighten the rules (fewer ruptures)")
    if regularised is not None:
        result.notes.append(f"the rates ({relation}) are {regularised}")
    if moved > 0:
        result.notes.append(f"the rates ({relation}): the slip budget and the shape conflict here; the least-squares "
                            f"rates released the budget to {moved:.0e}, and the rates are the nearest that release "
                            "it exactly")
    if result.budget_error > BUDGET_TOLERANCE:
        raise SolverError(f"the rupture rates ({relation}) release the slip rates only to {result.budget_error:.1e}, "
                          f"not {BUDGET_TOLERANCE:g}; loosen the rules (more ruptures)")
    return result


def _least_squares(matrix: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """The non-negative least-squares answer: scipy's NNLS, checked. NNLS at times stops short of the minimum and
    reports a residual its answer does not have (on a drawn rule set at the budget weight 1e5: 26.798 reported,
    26.8086 had, the minimum 26.8075), which moved the fitted values by 1e-6 under a 1e-12 change in the slips.
    Where its answer is not stationary on its own nonzero rates (the gradient there above 1e-10 of |A| |b|),
    BVLS (scipy's lsq_linear) solves it too, and the smaller residual is taken."""
    from scipy.optimize import lsq_linear, nnls  # heavy: imported where used

    x, _ = nnls(matrix, rhs, maxiter=50 * matrix.shape[1])
    residual = rhs - matrix @ x
    gradient = matrix[:, x > 0].T @ residual
    scale = float(np.max(np.abs(matrix))) * float(np.linalg.norm(rhs))
    if gradient.size == 0 or np.max(np.abs(gradient)) <= 1e-10 * scale:
        return x
    other = np.maximum(lsq_linear(matrix, rhs, bounds=(0.0, np.inf), method="bvls", tol=1e-14).x, 0.0)  # its round-off
    return other if np.linalg.norm(rhs - matrix @ other) < np.linalg.norm(residual) else x


def least_norm_rates(matrix: np.ndarray, fitted: np.ndarray, start: np.ndarray) -> tuple:
    """The least-norm non-negative [rates; c] with ``matrix @ [rates; c] = fitted``, c (the last column, the
    shape's level) unpenalised.

    The problem min ½‖x‖² subject to A x = d, x ≥ 0 has the dual min_y θ(y) = ½‖max(0, Aᵀy)‖² − dᵀy, whose
    minimiser gives x = max(0, Aᵀy) (Mangasarian 2004, eq. 3). With c unpenalised and c > 0, its multiplier
    makes y orthogonal to c's column, so y is sought in the complement of that column; c then closes the rows
    (least squares), and where it would be negative c = 0 and the rows are met by the rates alone. The rows are met
    to 10 × :data:`LEAST_NORM_TOLERANCE` (relative, each row scaled to a largest entry of 1).

    Parameters
    ----------
    matrix : ndarray
        The NNLS matrix (rows: sections' budgets and the shape's bins; columns: scaled rates, then c).
    fitted : ndarray
        NNLS's fitted values, ``matrix @ start``, which every minimiser shares.
    start : ndarray
        NNLS's solution: the answer where it is the only point that fits (:func:`_single_point`), where the dual
        has no minimum.

    Returns
    -------
    tuple
        (the solution [rates; c], None); (the solution, what it is) where the rates that fit are nearly one point
        and the solution is the ridge's least-norm rates (:data:`REGULARISED_TOLERANCE`); or (None, why it failed).

    Reference: O. L. Mangasarian, "A Newton method for linear programming", J. Optim. Theory Appl. 121 (2004) 1-18.
    """
    norms = np.max(np.abs(matrix), axis=1)
    norms[norms == 0] = 1.0
    rows, target = matrix / norms[:, None], fitted / norms  # rows rescaled: the same solutions, better conditioned
    level = rows[:, -1]
    basis = np.linalg.qr(level[:, None], mode="complete")[0][:, 1:]  # the complement of c's column
    rates, why = _dual_newton(basis.T @ rows[:, :-1], basis.T @ target)
    if rates is not None:
        c = float(level @ (target - rows[:, :-1] @ rates) / (level @ level))
        if c < 0:  # c's bound is active: c = 0, and the rates meet every row
            rates, why = _dual_newton(rows[:, :-1], target)
            c = 0.0
    largest = max(float(np.max(np.abs(target))), np.finfo(float).tiny)
    met = np.inf if rates is None else float(np.max(np.abs(rows @ np.append(rates, c) - target))) / largest
    if met <= 10 * LEAST_NORM_TOLERANCE:  # the proximal loop's last digit is round-off's
        return np.append(rates, c), None
    # the dual's minimum is not attained where the rates that fit are a single point: then that point is NNLS's
    if _single_point(rows, start):
        return start.copy(), None
    if met <= REGULARISED_TOLERANCE:  # nearly a point: the first proximal minimum, the ridge's least-norm rates
        return np.append(rates, c), (f"the least-norm rates of a ridge of {LEAST_NORM_RIDGE:g} (the rates that fit "
                                     f"are nearly one point, and the ridge's meet the rows to {met:.0e})")
    return None, why or f"it met the rows only to {met:.1e}, not {LEAST_NORM_TOLERANCE:g}"


def _single_point(rows: np.ndarray, point: np.ndarray) -> bool:
    """Whether ``point`` (>= 0) is the only non-negative solution of rows @ x = rows @ point: its nonzero columns are
    independent, and no non-negative mix of the others lies in their span (to :data:`LEAST_NORM_TOLERANCE`, by
    NNLS on the mixes of unit sum)."""
    from scipy.optimize import nnls  # heavy: imported where used

    support = point > 0
    if np.linalg.matrix_rank(rows[:, support]) < support.sum():
        return False
    if support.all():
        return True
    basis = np.linalg.qr(rows[:, support])[0] if support.any() else np.zeros((rows.shape[0], 0))
    others = rows[:, ~support] - basis @ (basis.T @ rows[:, ~support])
    mixes = np.vstack([others, np.ones((1, others.shape[1]))])
    _, miss = nnls(mixes, np.append(np.zeros(rows.shape[0]), 1.0), maxiter=50 * mixes.shape[1])
    return miss > LEAST_NORM_TOLERANCE


def project_onto_budget(rates: np.ndarray, slip_rows: np.ndarray) -> tuple:
    """The non-negative rates nearest ``rates`` (Euclidean, in the scaled rates) that release every budget,
    ``slip_rows @ rates = 1``: (rates, None), or (None, why). Unique, as a projection onto a convex set; found by
    :func:`_dual_newton` with ``rates`` as its offset."""
    norms = np.max(np.abs(slip_rows), axis=1)
    return _dual_newton(slip_rows / norms[:, None], 1.0 / norms, offset=rates)


def _dual_newton(rows: np.ndarray, target: np.ndarray, offset=None) -> tuple:
    """min ½‖x − offset‖² subject to rows @ x = target, x ≥ 0 (offset 0 if None): (x, None), or (None, why).

    Mangasarian's (2004) generalised Newton method on the dual, whose minimiser y gives x = max(0, offset + rowsᵀy),
    inside a proximal-point loop (R. T. Rockafellar, Math. Oper. Res. 1 (1976) 97-116): each dual carries
    ½ ρ ‖y − anchor‖², so it is strongly convex and its minimum attained; the anchor then moves to that minimum,
    and the rows are met ever closer. An Armijo line search and a Levenberg-Marquardt damping keep each Newton step
    descending. It starts from y = 0, so the answer depends on the problem only. Where the steps run out after a
    proximal minimum was reached, the first one's rates (the ridge's least-norm rates) are returned, and the caller
    checks how well they meet the rows."""
    if rows.shape[0] == 0:
        return (np.zeros(rows.shape[1]) if offset is None else np.maximum(offset, 0.0)), None
    offset = np.zeros(rows.shape[1]) if offset is None else offset
    largest = max(float(np.max(np.abs(target))), np.finfo(float).tiny)
    unit = max(float(np.max(np.sum(rows * rows, axis=1))), 1.0)  # the Hessian's scale
    proximal = LEAST_NORM_RIDGE * unit
    y = anchor = np.zeros(rows.shape[0])

    def dual(y):
        x = np.maximum(offset + rows.T @ y, 0.0)
        return x, 0.5 * (x @ x) - target @ y + 0.5 * proximal * ((y - anchor) @ (y - anchor))

    x, value = dual(y)
    damping, reached = 0.0, None
    for _ in range(LEAST_NORM_STEPS):
        residual = rows @ x - target
        met = np.max(np.abs(residual)) / largest
        if met <= LEAST_NORM_TOLERANCE:
            return x, None
        support = x > 0
        active = rows[:, support]
        if met <= 1e3 * LEAST_NORM_TOLERANCE:  # near: on this support, the nearest rates that meet the rows
            polished = np.zeros_like(x)
            polished[support] = offset[support] + np.linalg.lstsq(active, target - active @ offset[support],
                                                                  rcond=None)[0]
            if (np.all(polished >= 0) and np.max(np.abs(polished - x)) <= 1e-6 * np.max(x)
                    and np.max(np.abs(rows @ polished - target)) <= LEAST_NORM_TOLERANCE * largest):
                return polished, None
        gradient = residual + proximal * (y - anchor)
        if np.max(np.abs(gradient)) <= LEAST_NORM_TOLERANCE * largest:  # this proximal dual's minimum
            reached = x if reached is None else reached  # the first: the ridge's answer, the problem's alone
            anchor = y.copy()
            x, value = dual(y)
            gradient = residual
        hessian = active @ active.T + proximal * np.eye(rows.shape[0])  # the generalised Hessian
        while True:
            try:
                step = -np.linalg.solve(hessian + damping * np.eye(hessian.shape[0]), gradient)
            except np.linalg.LinAlgError:
                return None, "its Newton system was singular"
            slope = float(gradient @ step)
            for length in (1.0, 0.5, 0.25, 0.125):  # Armijo on the dual, to its round-off near the minimum
                trial_x, trial = dual(y + length * step)
                if trial <= value + 1e-4 * length * slope + 1e-14 * max(abs(value), 0.5 * (x @ x), 1.0):
                    break
            else:
                damping = max(100.0 * damping, proximal)
                if damping > 1e12 * unit:
                    if reached is not None:
                        return reached, None
                    return None, (f"its line search stalled with the rows met to {met:.1e}, not "
                                  f"{LEAST_NORM_TOLERANCE:g}")
                continue
            break
        if length == 1.0:
            damping = damping / 10.0 if damping > proximal else 0.0
        y, x, value = y + length * step, trial_x, trial
    if reached is not None:
        return reached, None
    return None, (f"{LEAST_NORM_STEPS} Newton steps met the rows only to "
                  f"{np.max(np.abs(rows @ x - target)) / largest:.1e}, not {LEAST_NORM_TOLERANCE:g}")


def _onto_budget(x: np.ndarray, rows: np.ndarray):
    """``x`` corrected by the least-norm step on its nonzero entries so that ``rows @ x = 1`` to round-off; ``x``
    itself where that step would make a rate negative and ``x`` meets the budget to a tenth of its tolerance
    already; else None."""
    active = np.flatnonzero(x > 0)
    if active.size == 0:
        return None
    residual = 1.0 - rows @ x
    close = np.max(np.abs(residual)) <= BUDGET_TOLERANCE / 10
    # a step of round-off's size: directions the active columns barely span (singular values below 1e-8 of the
    # largest) would turn it into a large move that round-off chooses
    step = np.linalg.lstsq(rows[:, active], residual, rcond=1e-8)[0]
    corrected = x.copy()
    corrected[active] += step
    roundoff = corrected[active] > -1e-12 * corrected[active].max()
    corrected[active] = np.where(roundoff, np.maximum(corrected[active], 0.0), corrected[active])
    if np.any(corrected[active] < 0) or np.max(np.abs(rows @ corrected - 1.0)) > np.max(np.abs(residual)):
        return x if close else None
    return corrected


def rupture_set(spec, dataset, rules: Rules, relation: str = "faultslip", stable_continental: bool = False,
                bin_width: float = 0.1, allow_large: bool = False) -> RuptureSet:
    """The map's fault system on ``relation``'s branch: sections, ruptures, magnitudes and solved rates.

    Parameters
    ----------
    spec : MapSpec
        A segment map (:func:`faultslip.studies.maps.read_map`).
    dataset : xarray.Dataset
        Its predictions (:func:`faultslip.studies.maps.run_map`).
    rules : Rules
        :func:`parse_rules`'s rules.
    relation : str
        faultslip, WC1994 or Leonard2010.
    stable_continental : bool
        Leonard's stable-continental relations.
    bin_width : float
        The target's magnitude bins.
    allow_large : bool
        Solve even beyond the memory and time budget (:func:`rate_estimate`, checked by
        :func:`faultslip.io.budget.check` before the rate problem's arrays are allocated).

    Returns
    -------
    RuptureSet
    """
    sections = fault_sections(spec, dataset, rules)
    ruptures = enumerate_ruptures(sections, rules)
    budget.check(rate_estimate(sections.count, len(ruptures), (relation,)), allow_large)
    shear_modulus = float(spec.scene.fault().shear_modulus)
    magnitude, slip = rupture_magnitudes(sections, ruptures, relation, shear_modulus, stable_continental)
    result = solve_rates(sections, ruptures, magnitude, slip, rules, relation, shear_modulus, bin_width)
    result.notes.append(f"{relation}: {sections.count} sections, {len(ruptures)} ruptures "
                        f"({int((result.rate > 0).sum())} with a rate), slip rates released to "
                        f"{result.budget_error:.1e}; {describe_b_value(result.b_value_fit())}")
    return result


def rate_estimate(sections: int, ruptures: int, relations=("faultslip",), enumerated: bool = True
                  ) -> budget.Estimate:
    """What solving the rates of ``ruptures`` ruptures over ``sections`` sections on each of ``relations``' branches
    needs, before its arrays are allocated.

    memory = :data:`RATE_MATRIX_COPIES` x 8 B x (sections + :data:`RATE_BIN_ROWS`) x ruptures (one branch at a time),
    seconds = branches x (overhead + c x (sections + :data:`RATE_BIN_ROWS`)^2 x ruptures), plus each branch's
    enumeration and magnitudes (per rupture) where ``enumerated`` is False (:data:`RATE_SOLVE_SECONDS`, fitted by
    ``benchmarks/rupture_rate_cost.py``; on this machine now, :func:`faultslip.io.machine.on_this_machine`).

    Parameters
    ----------
    sections, ruptures : int
        The system's sections and the ruptures its rules allow (:func:`enumerate_ruptures`).
    relations : sequence of str
        The branches solved, one after another.
    enumerated : bool
        Whether the ruptures are already enumerated (then only the solves are counted).

    Returns
    -------
    faultslip.io.budget.Estimate
    """
    rows = sections + RATE_BIN_ROWS
    fit = RATE_SOLVE_SECONDS
    per_branch = fit["overhead_seconds"] + fit["rate_seconds"] * rows ** 2 * ruptures + (
        0.0 if enumerated else fit["enumeration_seconds"] * ruptures)
    names = ", ".join(relations)
    return budget.Estimate(what=f"the rupture rates ({names}) of {ruptures:,} ruptures over {sections:,} sections "
                                "as the rules' max_jump, max_sections and section length allow",
                           memory=RATE_MATRIX_COPIES * 8.0 * rows * ruptures,
                           seconds=machine.on_this_machine(len(relations) * per_branch, "families"),
                           imports=("scipy.optimize",))


def rupture_set_estimate(spec, rules: Rules, relations=("faultslip",)) -> budget.Estimate:
    """What a map's rupture sets on ``relations``' branches need (:func:`rate_estimate`), before any prediction:
    their ruptures enumerated from the sections' geometry (:func:`fault_sections` without a dataset), which a
    rule set allows whatever the predictions are."""
    sections = fault_sections(spec, None, rules)
    ruptures = enumerate_ruptures(sections, rules)
    return rate_estimate(sections.count, len(ruptures), tuple(relations), enumerated=False)


def describe_b_value(fit: dict) -> str:
    """The solved distribution's b-value in words, always with its fit (:meth:`RuptureSet.b_value_fit`)."""
    if fit["log_rate_rms"] is None:
        return f"no b-value: the solved distribution has rates in {fit['bins']} magnitude bin(s)"
    low, high = fit["b_over_cutoffs"]
    words = (f"b-value of the solved distribution {fit['b']:.3f} (log10-rate residuals {fit['log_rate_rms']:.2g} RMS, "
             f"{fit['log_rate_max']:.2g} at most, over {fit['bins']} bins; {low:.3f}-{high:.3f} over lower cutoffs)")
    if not fit["gutenberg_richter"]:
        words += (f"; the solved rates are not Gutenberg-Richter (a bin lies {fit['log_rate_max']:.2g} in log10 off "
                  "the line): read the magnitude-frequency distribution, not b")
    return words


# --- what the engine reads -------------------------------------------------------------------------------

def nrml_sections(result: RuptureSet) -> list[dict]:
    """The sections as :func:`faultslip.io.nrml.write_sections` takes them."""
    s = result.sections
    return [{"name": s.names[i], "trace": s.traces[i], "dip": s.dip[i], "upper_depth": s.upper_depth[i],
             "lower_depth": s.lower_depth[i]} for i in range(s.count)]


def nrml_ruptures(result: RuptureSet) -> list[dict]:
    """The ruptures as :func:`faultslip.io.nrml.write_multi_fault_model` takes them (each with the rake of its
    largest section)."""
    area = result.sections.area
    rows = []
    for k, members in enumerate(result.ruptures):
        members = list(members)
        rows.append({"magnitude": result.magnitude[k], "sections": members, "rate": result.rate[k],
                     "rake": float(result.sections.rake[members][np.argmax(area[members])])})
    return rows


#: how far the background's polygon reaches beyond the faults' convex hull (m)
BACKGROUND_MARGIN = 20e3


def background_source(result: RuptureSet, bin_width: float = 0.1, moment_constant: float = mfds.MOMENT_CONSTANT):
    """The background share as an area source: the faults' convex hull widened by :data:`BACKGROUND_MARGIN`, a
    truncated Gutenberg-Richter distribution of the rules' b-value and magnitudes carrying its moment rate (None
    without a background share)."""
    from scipy.spatial import ConvexHull  # heavy: imported where used

    if not result.background_moment_rate > 0:
        return None
    points = np.vstack(result.sections.traces)
    centre = points.mean(axis=0)
    try:
        hull = points[ConvexHull(points).vertices]
    except Exception:  # noqa: BLE001 - collinear traces have no hull: a box around them instead
        low, high = points.min(axis=0), points.max(axis=0)
        hull = np.array([[low[0], low[1]], [high[0], low[1]], [high[0], high[1]], [low[0], high[1]]])
    polygon = np.array([destination(lon, lat, azimuth(centre, (lon, lat)), BACKGROUND_MARGIN) for lon, lat in hull])
    low, high = result.rules.background_magnitudes
    distribution = mfds.build("truncated_gr", result.background_moment_rate, high, low, result.rules.b_value,
                              bin_width, moment_constant)
    return {"polygon": polygon, "upper_depth": float(result.sections.upper_depth.min()),
            "lower_depth": float(result.sections.lower_depth.max()), "mfd": distribution,
            "rake": float(np.median(result.sections.rake))}
