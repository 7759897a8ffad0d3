"""Synthetic records as obspy Streams (miniSEED, SAC), and lab records read back from them.

Channel codes follow the SEED convention band + instrument + component. The band code comes from
the sampling rate (SEED manual, Appendix A, broadband family: F >= 1000 Hz, C >= 250, H >= 80,
B >= 10, M > 1, L ~ 1, V ~ 0.1, U ~ 0.01, R 1e-3-1e-4, P 1e-4-1e-5, T 1e-5-1e-6, Q < 1e-6). The
instrument code is Y ("non-specific instrument": these are models, not sensors). The component
code names the quantity, in SI:

====  ======================================  =====
code  quantity                                units
====  ======================================  =====
D     displacement of the slider              m
V     velocity of the slider                  m/s
A     acceleration of the slider              m/s^2
N     force (friction force)                  N
S     slip: cumulative sliding distance       m
R     slip rate: sliding speed                m/s
F     friction coefficient                    1
====  ======================================  =====

miniSEED stores float64 samples and no units, SAC float32 with one file per trace
(``STEM.COMPONENT.sac``, e.g. ``run.V.sac``); the mapping above is how ``faultslip record`` reads
them back.

A stream faultslip writes carries a checksum of its traces (:func:`traces_checksum`: codes, start, rate,
length and samples, as a reader finds them), checked where it is read back: in miniSEED a first record on
the SEED log channel ``LOG`` (ASCII text, which other programs read or skip as a station log), in SAC the
header's user fields (``kuser0`` marks it, ``kuser1`` and ``kuser2`` hold the first 16 hex digits). A
record that does not match is refused; one of an older faultslip (station FSLIP, no checksum) is read with
a warning; another program's carries nothing to check.
"""

from __future__ import annotations

import hashlib
import io
import json
import math
import re
import warnings
from pathlib import Path

from faultslip.constants import JULIAN_YEAR
import numpy as np

from faultslip.errors import InputError
from faultslip.io import gate
from faultslip.io.atomic import atomic_path
from faultslip.units import takes_units

COMPONENTS = {"D": ("displacement", "m"), "V": ("velocity", "m/s"), "A": ("acceleration", "m/s^2"),
              "N": ("force", "N"), "S": ("slip", "m"), "R": ("slip_rate", "m/s"), "F": ("friction_coefficient", "1")}
STREAM_SUFFIXES = {".mseed": "MSEED", ".miniseed": "MSEED", ".sac": "SAC"}
#: at most this many samples per trace unless the caller allows more
MAX_SAMPLES = 2_000_000
#: a record read back holds at most this many samples per channel (400 MB of float64)
MAX_READ_SAMPLES = 50_000_000
_BANDS = ((1000.0, "F"), (250.0, "C"), (80.0, "H"), (10.0, "B"), (1.0 + 1e-9, "M"), (0.5, "L"), (0.05, "V"),
          (0.005, "U"), (1e-4, "R"), (1e-5, "P"), (1e-6, "T"), (0.0, "Q"))


#: Model time 0 of a stream or catalog when no start time is given: 2000-01-01T00:00:00 UTC, in s since 1970.
DEFAULT_START = 946684800.0


def band_code(sampling_rate: float) -> str:
    """The SEED band code of a sampling rate (Hz), broadband family."""
    if not (sampling_rate > 0 and math.isfinite(sampling_rate)):
        raise InputError(f"the sampling rate must be positive, got {sampling_rate!r}")
    return next(code for low, code in _BANDS if sampling_rate >= low)


def stream_format(path) -> str:
    suffix = Path(path).suffix.lower()
    if suffix not in STREAM_SUFFIXES:
        raise InputError(f"{Path(path).name}: a stream is written as miniSEED (.mseed, .miniseed) or SAC (.sac), "
                         f"not {suffix or '(no suffix)'!r}")
    return STREAM_SUFFIXES[suffix]


#: The last instant miniSEED, SAC and QuakeML can date (obspy's UTCDateTime ends with year 9999).
LAST_DATABLE = 253402300799.0  # 9999-12-31T23:59:59 UTC, in s since 1970


def check_datable(start_seconds: float, span: float, cycles: int) -> None:
    """Refuse, in one sentence, a record that would end after year 9999 (its start in s since 1970, span in s)."""
    if start_seconds + span <= LAST_DATABLE:
        return
    years = span / JULIAN_YEAR
    fitting = int(cycles * (LAST_DATABLE - start_seconds) / span) - 1 if span > 0 else 0  # -1: the run ends past its last event
    raise InputError(f"the simulation spans {years:,.0f} years from its start time, past year 9999, the last that "
                     f"miniSEED, SAC and QuakeML can date; simulate at most {max(fitting, 0)} cycles (--cycles) or "
                     "give an earlier --start-time")


@takes_units(sampling_rate="frequency")
def build_stream(sampling_rate: float, channels: dict, start_seconds: float = DEFAULT_START, network: str = "XX",
                 station: str = "FSLIP", location: str = "00"):
    """An obspy Stream of uniformly sampled channels: ``channels`` maps a component code (see
    :data:`COMPONENTS`) to its samples (SI). ``start_seconds`` is the first sample's UTC time as seconds
    since 1970 (default 2000-01-01, a nominal epoch for model time).

    Parameters
    ----------
    sampling_rate : float
        Samples per second (Hz).
    channels : dict
        Component code -> samples in SI (m, m/s, N, ...).
    start_seconds : float
        UTC time of the first sample, in s since 1970.
    network, station, location : str
        SEED codes.

    Returns
    -------
    obspy.Stream
        One trace per component, with the units in each trace's stats.
    """
    from obspy import Stream, Trace, UTCDateTime  # heavy: imported where used

    band = band_code(sampling_rate)
    traces = []
    for component, samples in channels.items():
        if component not in COMPONENTS:
            raise InputError(f"unknown component {component!r}; allowed: {', '.join(COMPONENTS)}")
        samples = np.ascontiguousarray(samples, dtype=np.float64)
        header = {"network": network, "station": station[:5], "location": location, "channel": f"{band}Y{component}",
                  "sampling_rate": float(sampling_rate), "starttime": UTCDateTime(start_seconds)}
        traces.append(Trace(samples, header=header))
    return Stream(traces)


def sac_path(path, component: str) -> Path:
    """The SAC file of one component of a stream written to ``path`` (STEM.COMPONENT.sac)."""
    path = Path(path)
    return path.with_name(f"{path.stem}.{component}.sac")


#: The SEED channel of the record that carries a miniSEED file's checksum, and how its text starts.
CHECKSUM_CHANNEL, CHECKSUM_TEXT = "LOG", "faultslip sha256 "
#: ``kuser0`` of a SAC file faultslip wrote; ``kuser1`` + ``kuser2`` hold the first 16 hex digits of its checksum.
SAC_MARK = "fsha256"
#: The station code build_stream gives: a record with it and no checksum is an older faultslip's.
DEFAULT_STATION = "FSLIP"
#: How far into a miniSEED file its checksum record lies (it is the first record, of at most 8 kiB as obspy writes).
CHECKSUM_HEAD = 8192
_CHECKSUM_RECORD = re.compile(re.escape(CHECKSUM_TEXT.encode("ascii")) + rb"[0-9a-f]{64}")


def traces_checksum(headers, samples) -> str:
    """SHA-256 of traces as a reader finds them: each trace's SEED id, start (ns), sampling rate and length,
    from ``headers`` (obspy Traces, their data unused), and its samples, from ``samples`` (arrays in the same
    order), little-endian in the dtype they are stored in.

    Parameters
    ----------
    headers : iterable of obspy.Trace
        The traces' headers, in file order.
    samples : iterable of numpy.ndarray
        Their samples.

    Returns
    -------
    str
        64 hex digits.
    """
    digest = hashlib.sha256()
    for trace, data in zip(headers, samples, strict=True):
        data = np.asarray(data)
        stats = trace.stats
        digest.update(json.dumps([trace.id, int(stats.starttime.ns), repr(float(stats.sampling_rate)), int(stats.npts),
                                  data.dtype.kind, data.dtype.itemsize]).encode("utf-8"))
        digest.update(np.ascontiguousarray(data, dtype=data.dtype.newbyteorder("<")).tobytes())
    return digest.hexdigest()


def write_stream(stream, path) -> list:
    """miniSEED (float64, one file) or SAC (float32, ``STEM.COMPONENT.sac`` per trace), atomically, each
    carrying the checksum of its traces (module docstring). Returns the paths written.

    Parameters
    ----------
    stream : obspy.Stream
        The stream.
    path : str or path
        .mseed or .sac.

    Returns
    -------
    list
        The paths written.
    """
    from obspy import Stream, Trace, read  # heavy: imported where used

    path = Path(path)
    kind = stream_format(path)
    if kind == "MSEED":
        with atomic_path(path) as temporary, gate.quiet():  # obspy reports each failed record on stderr
            body = io.BytesIO()
            stream.write(body, format="MSEED", encoding="FLOAT64")
            # the headers as a reader finds them (the start to 1 us, the rate as SEED's factor and multiplier);
            # the samples are the float64 values written
            headers = read(io.BytesIO(body.getvalue()), format="MSEED", headonly=True)
            checksum = traces_checksum(headers, [np.asarray(trace.data, dtype=np.float64) for trace in stream])
            first = stream[0].stats
            log = Trace(np.frombuffer((CHECKSUM_TEXT + checksum).encode("ascii"), dtype="S1").copy(),
                        header={"network": first.network, "station": first.station, "location": first.location,
                                "channel": CHECKSUM_CHANNEL, "sampling_rate": 0.0, "starttime": first.starttime})
            head = io.BytesIO()
            Stream([log]).write(head, format="MSEED", encoding="ASCII")
            # first, so that a file cut short still holds the checksum its remaining records fail
            with open(temporary, "wb") as handle:
                handle.write(head.getbuffer())
                handle.write(body.getbuffer())
        return [path]
    written = []
    for trace in stream:
        target = sac_path(path, trace.stats.channel[-1])
        with atomic_path(target) as temporary, gate.quiet():
            trace = trace.copy()
            trace.write(str(temporary), format="SAC")
            found = read(str(temporary), format="SAC")[0]  # as a reader finds it: float32, the start to 1 ms + b
            checksum = traces_checksum([found], [found.data])
            trace.stats.sac = found.stats.sac
            trace.stats.sac.update({"kuser0": SAC_MARK, "kuser1": checksum[:8], "kuser2": checksum[8:16]})
            trace.write(str(temporary), format="SAC")
        written.append(target)
    return written


def _checked(stream, path: Path, kind: str):
    """``stream`` without faultslip's checksum record, once its traces match it (module docstring); one sentence
    if they do not, or if the checksum itself was damaged."""
    if kind == "MSEED":
        # text traces and log channels: faultslip's checksum, or another program's station log
        texts = [t for t in stream if t.stats.channel == CHECKSUM_CHANNEL or t.data.dtype.kind == "S"]
        ours = [t for t in texts if _CHECKSUM_RECORD.fullmatch(t.data.tobytes())]
        # a checksum record whose header was damaged is skipped by the decoder: its text is still in the file
        written = CHECKSUM_TEXT.encode("ascii") in gate.read_head(path, "record", "waveform", CHECKSUM_HEAD)
        damaged = not ours and (written or any(b"faultslip" in t.data.tobytes() or t.stats.station == DEFAULT_STATION
                                               for t in texts))
        stated = [t.data.tobytes()[len(CHECKSUM_TEXT):].decode("ascii") for t in ours]
        traces = stream.__class__([t for t in stream if not any(t is text for text in texts if ours or damaged)])
        found = traces_checksum(traces, [trace.data for trace in traces]) if ours else None
    else:
        sac = stream[0].stats.get("sac", {})
        users = [str(sac.get(key, "")) for key in ("kuser0", "kuser1", "kuser2")]
        stated = [users[1] + users[2]] if users[0] == SAC_MARK else []
        damaged = not stated and any(users) and stream[0].stats.station == DEFAULT_STATION
        traces = stream
        found = traces_checksum(traces, [trace.data for trace in traces])[:16] if stated else None
    if len(stated) > 1:
        raise InputError(f"record {path.name} carries {len(stated)} checksum records; faultslip writes one")
    if damaged:
        raise InputError(f"record {path.name} carries a damaged faultslip checksum, so its samples cannot be "
                         "checked; write it again (faultslip simulate --stream)")
    if stated and stated[0] != found:
        raise InputError(f"record {path.name} does not match the checksum faultslip wrote with it: its samples or "
                         "headers were edited or damaged since; write it again (faultslip simulate --stream)")
    if not stated and all(trace.stats.station == DEFAULT_STATION for trace in traces):
        warnings.warn(f"record {path.name} was written by a faultslip that did not yet add a checksum to its "
                      "streams: it is read unchecked", stacklevel=3)
    return traces


def read_stream(path):
    """A miniSEED or SAC file through obspy.read, in one sentence if it is not one.

    Parameters
    ----------
    path : str or path
        The waveform file.

    Returns
    -------
    obspy.Stream
    """
    from obspy import read  # heavy: imported where used

    path = gate.check_input(path, "record", "waveform")
    kind = stream_format(path)
    # obspy prints "Exception ignored" reports and multi-line warnings for a damaged record: silenced
    with gate.decoding(path, "record", "miniSEED" if kind == "MSEED" else "SAC", silence=True):
        headers = read(str(path), format=kind, headonly=True)  # sizes first: a corrupt header can claim anything
        total = sum(int(trace.stats.npts) for trace in headers)
        if total > MAX_READ_SAMPLES:
            raise InputError(f"{path.name} holds {total:,} samples; the limit is {MAX_READ_SAMPLES:,}")
        stream = read(str(path), format=kind)
    if len(stream) == 0:
        raise InputError(f"{path.name} holds no traces")
    stream = _checked(stream, path, kind)
    if len(stream) == 0:
        raise InputError(f"{path.name} holds no traces besides its checksum")
    return stream


def channels_by_quantity(stream, source: str) -> tuple[np.ndarray, dict]:
    """(time in s from the first sample, {quantity: samples}) from a Stream, by the component code of each
    channel; the traces must share their start, rate and length (merged per channel first)."""
    stream = stream.copy()
    for trace_id in {trace.id for trace in stream}:  # a gap is filled: bound the joined length first
        parts = [trace for trace in stream if trace.id == trace_id]
        span = max(t.stats.endtime for t in parts) - min(t.stats.starttime for t in parts)
        if span * max(t.stats.sampling_rate for t in parts) > MAX_READ_SAMPLES:
            raise InputError(f"{source}: channel {trace_id} spans {span:.4g} s at {parts[0].stats.sampling_rate:g} Hz, "
                             f"more than {MAX_READ_SAMPLES:,} samples once its gaps are filled")
    try:
        stream.merge(method=1, fill_value="interpolate")
    except Exception as exc:  # obspy raises a bare Exception for traces it cannot join (e.g. differing rates)
        raise InputError(f"{source}: the records of one channel cannot be joined ({str(exc).splitlines()[0][:120]})") \
            from None
    found = {}
    reference = None
    for trace in stream:
        component = trace.stats.channel[-1:].upper()
        if component not in COMPONENTS:
            continue
        quantity = COMPONENTS[component][0]
        if quantity in found:
            raise InputError(f"{source}: two channels carry the {quantity} ({component}); keep one station and location")
        stats = (float(trace.stats.starttime.timestamp), float(trace.stats.sampling_rate), int(trace.stats.npts))
        if reference is None:
            reference = stats
        elif abs(stats[0] - reference[0]) > 0.5 / reference[1] or stats[1] != reference[1] or stats[2] != reference[2]:
            raise InputError(f"{source}: the channels differ in start, sampling rate or length; trim them to one window")
        data = np.asarray(trace.data, dtype=float)
        if not np.all(np.isfinite(data)):
            raise InputError(f"{source}: channel {trace.stats.channel} has non-finite samples")
        found[quantity] = data
    if reference is None:
        raise InputError(f"{source}: no channel ends in a known component code ({', '.join(COMPONENTS)}: "
                         + ", ".join(f"{c} {q}" for c, (q, _) in COMPONENTS.items()) + ")")
    time = np.arange(reference[2]) / reference[1]
    return time, found
