"""The antiplane elastic stress of uniform-slip elements on a vertical fault in a half-space.

A screw dislocation patch with uniform slip s from depth d1 to d2 (z positive down) in a full space
changes the shear stress on the fault plane at depth z by (Segall 2010, Earthquake and Volcano
Deformation, eq. 2.xx for a screw dislocation; Rice 1993, JGR 98, 9885):

    tau(z) = G s / (2 pi) [1 / (z - d2) - 1 / (z - d1)].

The traction-free surface z = 0 is the image patch from -d2 to -d1 with the same slip:

    + G s / (2 pi) [1 / (z + d1) - 1 / (z + d2)].

On N elements of size h from the surface down (element j from j h to (j + 1) h), the stress at
the centre of element i, z_i = (i + 1/2) h, from unit slip on element j is

    K_ij = G / (2 pi h) [1/(i - j - 1/2) - 1/(i - j + 1/2) + 1/(i + j + 1/2) - 1/(i + j + 3/2)],

a Toeplitz part (depending on i - j) plus a Hankel part (on i + j). Both are convolutions, so K x
costs O(N log N) by FFT against O(N^2) dense. Uniform slip everywhere, down to infinite depth, is
a rigid motion with no stress: the rows of K plus the semi-infinite part below the last element
sum to zero, which is why the fault is written in slip deficit, K (delta - V_pl t).
"""

from __future__ import annotations

import dataclasses
import functools
import math

import numpy as np

from faultslip.errors import InputError
from faultslip.io.resources import read_bundled_table

#: The measured crossover (``data/kernel_crossover.json``, written by ``benchmarks/kernel_crossover.py``).
CROSSOVER_FILE = "kernel_crossover.json"
#: The paths a step can take, each with its own crossover: the whole step compiled (numba and rocket-fft), its
#: element-wise work compiled (numba; the FFT by scipy), or numpy alone.
STEP_PATHS = ("fused", "compiled", "numpy")


@functools.lru_cache(maxsize=1)
def measured_crossover() -> dict:
    """``data/kernel_crossover.json`` (``benchmarks/kernel_crossover.py``: BP1 at rtol 1e-4, interleaved, median per
    step), checked: per step path, ``dense_limit``, the element count at and below which a whole step with the dense
    product took less CPU than one with the FFT, and ``relative_step_cost``, its step's time over the fused path's."""
    table = read_bundled_table(CROSSOVER_FILE, "the stress kernel's measured crossover", "benchmarks/kernel_crossover.py")
    limits = table.get("dense_limit") if isinstance(table, dict) else None
    costs = table.get("relative_step_cost") if isinstance(table, dict) else None
    if not (isinstance(limits, dict) and all(isinstance(limits.get(name), int) and limits[name] >= 0
                                             for name in STEP_PATHS)
            and isinstance(costs, dict) and all(isinstance(costs.get(name), (int, float)) and 0 < costs[name] < 1e3
                                                for name in STEP_PATHS)):
        raise InputError(f"{CROSSOVER_FILE} lacks a whole dense_limit and a positive relative_step_cost for each of "
                         f"{', '.join(STEP_PATHS)}; rerun benchmarks/kernel_crossover.py")
    return {"dense_limit": {name: limits[name] for name in STEP_PATHS},
            "relative_step_cost": {name: float(costs[name]) for name in STEP_PATHS}}


def crossover(rows: list[dict]) -> float:
    """The element count from which the FFT step is faster at every larger count measured, taken midway in log N
    from the last count where the dense step won; ``rows`` hold ``elements``, ``dense_us`` and ``fft_us``."""
    rows = sorted(rows, key=lambda row: row["elements"])
    dense_wins = [row["elements"] for row in rows if row["dense_us"] <= row["fft_us"]]
    if not dense_wins:
        return rows[0]["elements"] / 2
    after = [row["elements"] for row in rows if row["elements"] > dense_wins[-1]]
    return math.sqrt(dense_wins[-1] * after[0]) if after else float(dense_wins[-1])


def chosen_cost(rows: list[dict], limit: float) -> dict:
    """Per element count, the time a step took with the kernel ``auto`` takes at that count (us)."""
    return {row["elements"]: row["dense_us"] if row["elements"] <= limit else row["fft_us"] for row in rows}


def relative_costs(tables: dict, limits: dict) -> dict:
    """Per step path, the median over element counts of its step's time over the fused path's, each with the kernel
    ``auto`` takes (what the cost model, fitted on fused runs, is scaled by on another path)."""
    fused = chosen_cost(tables["fused"], limits["fused"])
    out = {}
    for path in STEP_PATHS:
        mine = chosen_cost(tables[path], limits[path])
        ratios = sorted(mine[count] / fused[count] for count in mine if count in fused)
        out[path] = float(np.median(ratios))
    return out


def relative_step_cost(path: str) -> float:
    """How many times a fused step's time a step on ``path`` takes (:func:`measured_crossover`)."""
    if path not in STEP_PATHS:
        raise InputError(f"a step path is one of {', '.join(STEP_PATHS)}, got {path!r}")
    return measured_crossover()["relative_step_cost"][path]


def dense_limit(path: str = "numpy") -> int:
    """The element count at and below which ``method="auto"`` takes the dense product on step path ``path``."""
    if path not in STEP_PATHS:
        raise InputError(f"a step path is one of {', '.join(STEP_PATHS)}, got {path!r}")
    return measured_crossover()["dense_limit"][path]


def _toeplitz_column(count: int) -> np.ndarray:
    """t_k = 1/(k - 1/2) - 1/(k + 1/2) for k = 0 .. count - 1 (even in k)."""
    k = np.arange(count, dtype=float)
    return 1.0 / (k - 0.5) - 1.0 / (k + 0.5)


def _hankel_sequence(count: int) -> np.ndarray:
    """h_m = 1/(m + 1/2) - 1/(m + 3/2) for m = i + j = 0 .. 2 count - 2."""
    m = np.arange(2 * count - 1, dtype=float)
    return 1.0 / (m + 0.5) - 1.0 / (m + 1.5)


def dense_matrix(count: int, element_size: float, shear_modulus: float) -> np.ndarray:
    """K (Pa per m of slip) as a dense (count, count) matrix."""
    i = np.arange(count)[:, None]
    j = np.arange(count)[None, :]
    t = _toeplitz_column(count)[np.abs(i - j)]
    h = _hankel_sequence(count)[i + j]
    return shear_modulus / (2.0 * math.pi * element_size) * (t + h)


def deep_loading(count: int, element_size: float, shear_modulus: float) -> np.ndarray:
    """Stress at each element per metre of uniform slip on the fault below the last element."""
    depth = (np.arange(count) + 0.5) * element_size
    bottom = count * element_size
    return shear_modulus / (2.0 * math.pi) * (1.0 / (bottom - depth) + 1.0 / (depth + bottom))


def _spectra(count: int, length: int, scale: float) -> tuple[np.ndarray, np.ndarray]:
    """The FFT form's spectra at ``length`` (>= 2 N - 1): ``scale`` rfft of the Toeplitz column wrapped into a
    circulant, and of the Hankel sequence shifted by N - 1, times the reversal's phase (X_rev = phase conj(X))."""
    from scipy import fft  # heavy: imported where used

    t = _toeplitz_column(count)
    circulant = np.zeros(length)  # the symmetric Toeplitz column, wrapped: t_0..t_{N-1}, then t_{N-1}..t_1
    circulant[:count] = t
    circulant[length - count + 1:] = t[:0:-1]
    h = _hankel_sequence(count)
    shifted = np.zeros(length)  # g[m] = h[m + N - 1] for m in -(N-1)..N-1, wrapped
    shifted[:count] = h[count - 1:]
    shifted[length - count + 1:] = h[: count - 1]
    frequency = np.arange(length // 2 + 1)
    phase = np.exp(-2j * np.pi * frequency * (count - 1) / length)
    return scale * fft.rfft(circulant), scale * fft.rfft(shifted) * phase


class StressKernel:
    """``kernel(slip)`` is K slip (Pa), by a dense product for small N and by FFT above (``method="auto"``: the
    crossover measured for the step ``path`` that will use it, :func:`dense_limit`).

    The FFT form (length L >= 2 N - 1) takes the Toeplitz part as a circular convolution and the
    Hankel part as one with the reversed slip, shifted by N - 1; the reversed slip's spectrum is
    the conjugate of the slip's times a phase, so one forward and one inverse real FFT give K x.
    Its round-off against the dense product is ~1e-15 of the largest stress (tested).
    """

    def __init__(self, count: int, element_size: float, shear_modulus: float, method: str = "auto",
                 path: str = "numpy"):
        if count < 2:
            raise InputError(f"a 2-D fault needs at least 2 elements, got {count}")
        if method not in ("auto", "dense", "fft"):
            raise InputError(f"the stress kernel is dense, fft or auto, got {method!r}")
        self.count, self.element_size, self.shear_modulus = count, element_size, shear_modulus
        self.method = method if method != "auto" else ("dense" if count <= dense_limit(path) else "fft")
        scale = shear_modulus / (2.0 * math.pi * element_size)
        if self.method == "dense":
            self.matrix = dense_matrix(count, element_size, shear_modulus)
            self._padded = np.zeros(count)
            return
        from scipy import fft  # heavy: imported where used

        self._fft = fft
        length = fft.next_fast_len(2 * count - 1, real=True)
        self.length = length
        self._toeplitz_hat, self._hankel_hat = _spectra(count, length, scale)
        self._padded = np.zeros(length)

    @property
    def toeplitz_hat(self) -> np.ndarray:
        """The Toeplitz part's spectrum (FFT kernel only), G / (2 pi h) rfft(t), for a compiled product."""
        return self._toeplitz_hat

    @property
    def hankel_hat(self) -> np.ndarray:
        """The Hankel part's spectrum times the reversal's phase (FFT kernel only)."""
        return self._hankel_hat

    @functools.cached_property
    def halves(self) -> "SpectrumHalves":
        """The spectra and twiddles of :func:`spectrum_halves` for this kernel (FFT kernel only)."""
        return spectrum_halves(self.count, self.element_size, self.shear_modulus)

    @property
    def padded(self) -> np.ndarray:
        """The input buffer of :meth:`product_of_padded`: its first N values are the slip (the rest stays zero)."""
        return self._padded

    def product_of_padded(self) -> np.ndarray:
        """K x for the x in :attr:`padded` (its first N values are K x; an FFT's result runs on past them)."""
        if self.method == "dense":
            return self.matrix @ self._padded
        spectrum = self._fft.rfft(self._padded)
        both = self._toeplitz_hat * spectrum + self._hankel_hat * np.conj(spectrum)
        return self._fft.irfft(both, self.length)

    def __call__(self, slip: np.ndarray) -> np.ndarray:
        if self.method == "dense":
            return self.matrix @ slip
        self._padded[: self.count] = slip  # the tail stays zero: no padding copy inside the FFT
        return self.product_of_padded()[: self.count]


# --- K x in two halves of its spectrum (issue 43, item 3) -------------------------------------------------------
#
# With the slip zero-padded to L = 2 M (M >= N), the even bins of its DFT are the DFT of its first M values, and the
# odd bins that of x_n w^n (w = exp(-2 pi i / M) taken to the half power: W_L^n), each of length M. K x's spectrum
# at bin k takes X_k and X_{L-k} (the Hankel part's conjugate), of the same parity when L is even: so the even and
# the odd bins never meet, and K x = a + s, the even half's inverse a and the odd half's s, each found without the
# other. The odd half of a real signal needs half its bins (O_{M-1-j} = conj O_j) and is taken by one complex FFT of
# length M / 2 on the even and odd samples packed as real and imaginary parts (the real FFT's own packing; Press
# et al. 2007, Numerical Recipes, 3rd ed., sec. 12.3.2, with the half-bin twiddle w^(j + 1/2)), and its inverse
# likewise. Each half costs about half of the one real FFT of length L and its inverse: two threads take one each.


@dataclasses.dataclass(frozen=True)
class SpectrumHalves:
    """K x's spectrum split in its even and odd bins (:func:`spectrum_halves`), as the fused step takes them.

    ``table`` rows (complex, M / 2 + 1 columns; the odd rows' last column unused): 0 and 1 the Toeplitz and
    Hankel parts at the even bins 2 j, j = 0 .. M / 2; 2 and 3 at the odd bins 2 j + 1, j = 0 .. M / 2 - 1; 4
    the twiddle w^m and 5 the half-bin twiddle w^(m + 1/2), w = exp(-2 pi i / M), m = 0 .. M / 2 - 1."""

    half_length: int
    table: np.ndarray


#: the rows of :attr:`SpectrumHalves.table`
TOEPLITZ_EVEN, HANKEL_EVEN, TOEPLITZ_ODD, HANKEL_ODD, TWIDDLE, HALF_TWIDDLE = range(6)


def half_length(count: int) -> int:
    """M, the length of each half's transforms: even, at least ``count``, and M / 2 a fast length for a complex
    FFT (so that L = 2 M is one for the real FFT)."""
    from scipy import fft  # heavy: imported where used

    return 2 * fft.next_fast_len((count + 1) // 2)


def spectrum_halves(count: int, element_size: float, shear_modulus: float) -> SpectrumHalves:
    """The Toeplitz and Hankel spectra of :class:`StressKernel`'s FFT form at length L = 2 M
    (:func:`half_length`), split in even and odd bins, with the odd half's twiddles. The Hankel part's spectrum
    carries the reversal's phase, as :attr:`StressKernel.hankel_hat` does. The halves' inverse transforms are scaled
    by 1 / L, so that K x = a + s."""
    half = half_length(count)
    length = 2 * half
    toeplitz_hat, hankel_hat = _spectra(count, length, shear_modulus / (2.0 * math.pi * element_size))
    table = np.zeros((6, half // 2 + 1), dtype=complex)
    table[TOEPLITZ_EVEN], table[HANKEL_EVEN] = toeplitz_hat[0::2], hankel_hat[0::2]
    table[TOEPLITZ_ODD, :half // 2], table[HANKEL_ODD, :half // 2] = toeplitz_hat[1::2], hankel_hat[1::2]
    m = np.arange(half // 2)
    table[TWIDDLE, :half // 2] = np.exp(-2j * np.pi * m / half)
    table[HALF_TWIDDLE, :half // 2] = np.exp(-2j * np.pi * (m + 0.5) / half)
    return SpectrumHalves(half, table)
