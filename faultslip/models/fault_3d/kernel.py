"""The elastic tractions of uniform-slip rectangles on a planar fault in a half-space, and their product
by FFT along strike.

The fault is a plane through the x axis (the strike), dipping ``dip`` degrees towards +y, from the free surface
z = 0 down; it is cut into squares of side h, ``strike_count`` along strike and ``dip_count`` down dip. Each
square is three triangular dislocations (Nikkhoo & Walter 2015, GJI 201, 1119, "artefact-free" in a half-space,
computed by cutde), split so that the square's centre lies inside one triangle and never on an edge, where
the triangles' own fields are singular. The traction change at the centre of element (i, j) from unit slip on
element (k, l) along the rake is

    K[(i, j), (k, l)] = (sigma n) . s,        and the normal-stress change   N = -(sigma n) . n,

with n the fault's normal, s the slip direction (along strike, or up or down dip) and sigma the stress of the
source's dislocation (positive in tension; N positive in compression). A square's own slip drops the traction on
it: K[(i, j), (i, j)] < 0.

**Structure, not compression.** A planar fault with uniform spacing along a horizontal strike is invariant to
translation along strike, in a half-space as in a full space, so K depends on i - k, j and l only:
K[(i, j), (k, l)] = T[i - k, j, l]. The whole operator is then (2 N_x - 1) N_z^2 numbers, not (N_x N_z)^2, and its
product is a convolution along strike: one real FFT of each of the N_z rows, a dense N_z x N_z product at each of
N_x + 1 frequencies, and one inverse FFT (as QDYN does for 3-D faults; Luo et al. 2017). It is exact to
round-off: nothing is approximated, unlike an H-matrix's ACA (which would be needed for a non-planar fault or
non-uniform elements). Memory grows as N_x N_z^2 and a product as N_x N_z^2 + N_z N_x log N_x: N log N along
strike at a fixed depth resolution (``benchmarks/fault_3d_operator.py`` measures both).
"""

from __future__ import annotations

import math
import os

import numpy as np

from faultslip.errors import InputError

#: The slip directions a 3-D fault's elements slip along (the rake held fixed in time).
RAKES = ("strike", "thrust", "normal")
#: Observation points per cutde call while the operator is assembled (about 60 MB of strain a call).
_CHUNK = 20_000


def _cutde():
    """cutde's half-space module, its own OpenMP runtime held to one thread: libgomp is not fork-safe, and a
    process that had run a parallel region and then forked workers (a sweep after a run, in one notebook) hung
    them at their first kernel. Its runtime reads OMP_NUM_THREADS once, when the library loads, here."""
    previous = os.environ.get("OMP_NUM_THREADS")
    os.environ["OMP_NUM_THREADS"] = "1"
    try:
        import cutde.halfspace  # heavy: compiled triangular dislocations, imported where the 3-D fault is built
    finally:
        if previous is None:
            os.environ.pop("OMP_NUM_THREADS", None)
        else:
            os.environ["OMP_NUM_THREADS"] = previous
    return cutde.halfspace


def fault_axes(dip: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(strike, down-dip, normal) unit vectors of a plane dipping ``dip`` degrees towards +y (z up, the medium
    at z <= 0); the normal points to the hanging wall's side (+y, and up, on a dipping fault)."""
    angle = math.radians(dip)
    strike = np.array([1.0, 0.0, 0.0])
    down_dip = np.array([0.0, math.cos(angle), -math.sin(angle)])
    normal = np.cross(strike, down_dip)
    return strike, down_dip, normal


def slip_direction(rake: str, dip: float) -> np.ndarray:
    """The unit slip vector of the hanging wall (the +normal side) for ``rake``: along strike, up dip (thrust) or
    down dip (normal)."""
    strike, down_dip, _ = fault_axes(dip)
    return {"strike": strike, "thrust": -down_dip, "normal": down_dip}[rake]


def element_triangles(strike_from: np.ndarray, dip_from: np.ndarray, element_size: float, dip: float) -> np.ndarray:
    """The three triangles (k, 3 vertices, xyz) of each square whose up-dip corner nearest -x lies ``strike_from``
    along strike and ``dip_from`` down dip: (A, B, M), (A, M, D), (B, C, M), with A, B the up-dip edge, D, C the
    down-dip edge and M its midpoint, so that the square's centre lies inside (A, B, M). Every triangle's normal is
    the fault's (:func:`fault_axes`)."""
    strike, down_dip, _ = fault_axes(dip)
    x0 = np.asarray(strike_from, float)[:, None]
    s0 = np.asarray(dip_from, float)[:, None]
    h = element_size

    def point(along, down):
        return along * strike + down * down_dip

    a, b = point(x0, s0), point(x0 + h, s0)
    c, d, m = point(x0 + h, s0 + h), point(x0, s0 + h), point(x0 + h / 2, s0 + h)
    # each counter-clockwise seen from the normal's side, so that every triangle's normal is the fault's
    return np.stack([np.stack([a, b, m], axis=1), np.stack([a, m, d], axis=1), np.stack([b, c, m], axis=1)],
                    axis=1).reshape(-1, 3, 3)


def _tdcs_slip(tris: np.ndarray, direction: np.ndarray) -> np.ndarray:
    """``direction`` in each triangle's own (strike, dip, tensile) axes, as cutde takes slip (Nikkhoo & Walter
    2015: strike = e_z x normal, dip = normal x strike; never horizontal here, the dip being above 0)."""
    normal = np.cross(tris[:, 1] - tris[:, 0], tris[:, 2] - tris[:, 0])
    normal /= np.linalg.norm(normal, axis=1)[:, None]
    strike = np.cross(np.array([0.0, 0.0, 1.0]), normal)
    strike /= np.linalg.norm(strike, axis=1)[:, None]
    dip_axis = np.cross(normal, strike)
    return np.stack([strike @ direction, dip_axis @ direction, np.zeros(len(tris))], axis=1)


def cross_direction(rake: str, dip: float) -> np.ndarray:
    """The in-plane direction perpendicular to the slip (down dip for strike slip, along strike for dip slip): the
    traction there would turn the rake, which is held fixed."""
    _, _, normal = fault_axes(dip)
    return np.cross(normal, slip_direction(rake, dip))


def tractions(observation: np.ndarray, tris: np.ndarray, slips: np.ndarray, dip: float, rake: str,
              shear_modulus: float, poisson_ratio: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(shear along the rake, normal stress change, compression positive, shear across the rake,
    :func:`cross_direction`) at ``observation`` (n, 3) from the triangles ``tris`` with slips ``slips`` (k, 3, in
    the triangles' own axes), summed (Pa)."""
    halfspace = _cutde()
    _, _, normal = fault_axes(dip)
    direction = slip_direction(rake, dip)
    across = cross_direction(rake, dip)
    lam = 2.0 * shear_modulus * poisson_ratio / (1.0 - 2.0 * poisson_ratio)
    shear, normal_change = np.empty(len(observation)), np.empty(len(observation))
    cross = np.empty(len(observation))
    for start in range(0, len(observation), _CHUNK):
        chunk = slice(start, start + _CHUNK)
        strain = halfspace.strain_free(np.ascontiguousarray(observation[chunk]), tris, slips, poisson_ratio)
        strain = strain.sum(axis=1) if strain.ndim == 3 else strain
        stress = 2.0 * shear_modulus * strain
        stress[:, :3] += lam * strain[:, :3].sum(axis=1)[:, None]
        xx, yy, zz, xy, xz, yz = stress.T
        traction = np.stack([xx * normal[0] + xy * normal[1] + xz * normal[2],
                             xy * normal[0] + yy * normal[1] + yz * normal[2],
                             xz * normal[0] + yz * normal[1] + zz * normal[2]], axis=1)
        shear[chunk] = traction @ direction
        normal_change[chunk] = -(traction @ normal)
        cross[chunk] = traction @ across
    return shear, normal_change, cross


def centres(strike_index, dip_index, element_size: float, dip: float) -> np.ndarray:
    """The centres (n, 3) of elements (strike_index, dip_index), strike index 0 starting at x = 0."""
    strike, down_dip, _ = fault_axes(dip)
    along = (np.asarray(strike_index, float) + 0.5) * element_size
    down = (np.asarray(dip_index, float) + 0.5) * element_size
    return along[:, None] * strike + down[:, None] * down_dip


def _row_kernels(strike_count: int, dip_count: int, element_size: float, dip: float, rake: str,
                 shear_modulus: float, poisson_ratio: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """T[d, j, l], its normal and its cross-rake counterparts for offsets d = i - k from -(N_x - 1) to N_x - 1
    (index d + N_x - 1): the traction at element (k + d, j) from unit slip on element (k, l)."""
    offsets = np.arange(-(strike_count - 1), strike_count)
    grid_offsets, grid_rows = np.meshgrid(offsets, np.arange(dip_count), indexing="ij")
    observation = centres(grid_offsets.ravel(), grid_rows.ravel(), element_size, dip)
    shear = np.empty((offsets.size, dip_count, dip_count))
    normal, cross = np.empty_like(shear), np.empty_like(shear)
    direction = slip_direction(rake, dip)
    for row in range(dip_count):
        tris = element_triangles(np.zeros(1), np.array([row * element_size]), element_size, dip)
        slips = _tdcs_slip(tris, direction)
        s, n, c = tractions(observation, tris, slips, dip, rake, shear_modulus, poisson_ratio)
        shear[:, :, row] = s.reshape(offsets.size, dip_count)
        normal[:, :, row] = n.reshape(offsets.size, dip_count)
        cross[:, :, row] = c.reshape(offsets.size, dip_count)
    return shear, normal, cross


def dense_matrices(strike_count: int, dip_count: int, element_size: float, dip: float = 90.0, rake: str = "strike",
                   shear_modulus: float = 3.2e10, poisson_ratio: float = 0.25) -> tuple[np.ndarray, np.ndarray]:
    """The full (N, N) shear and normal matrices, N = N_x N_z, element (i, j) at index i N_z + j: every source
    element's own triangles, no translation used (the reference :class:`StrikeConvolution` is checked against)."""
    _check_grid(strike_count, dip_count, element_size, dip, rake, poisson_ratio)
    halfspace = _cutde()
    index_strike, index_dip = np.divmod(np.arange(strike_count * dip_count), dip_count)
    observation = centres(index_strike, index_dip, element_size, dip)
    count = index_strike.size
    tris = element_triangles(index_strike * element_size, index_dip * element_size, element_size, dip)
    slips = _tdcs_slip(tris, slip_direction(rake, dip))  # (3 N, 3): each triangle's slip in its own axes
    _, _, normal = fault_axes(dip)
    direction = slip_direction(rake, dip)
    lam = 2.0 * shear_modulus * poisson_ratio / (1.0 - 2.0 * poisson_ratio)
    shear, normal_change = np.empty((count, count)), np.empty((count, count))
    rows = max(1, _CHUNK // (3 * count) * 8)
    for start in range(0, count, rows):
        chunk = slice(start, min(start + rows, count))
        strain = halfspace.strain_matrix(np.ascontiguousarray(observation[chunk]), tris, poisson_ratio)
        strain = np.einsum("oitk,tk->oit", strain, slips).reshape(strain.shape[0], 6, count, 3).sum(axis=3)
        stress = 2.0 * shear_modulus * strain
        stress[:, :3] += lam * strain[:, :3].sum(axis=1)[:, None]
        xx, yy, zz, xy, xz, yz = (stress[:, k] for k in range(6))
        traction = np.stack([xx * normal[0] + xy * normal[1] + xz * normal[2],
                             xy * normal[0] + yy * normal[1] + yz * normal[2],
                             xz * normal[0] + yz * normal[1] + zz * normal[2]], axis=-1)
        shear[chunk] = traction @ direction
        normal_change[chunk] = -(traction @ normal)
    return shear, normal_change


def _check_grid(strike_count, dip_count, element_size, dip, rake, poisson_ratio) -> None:
    if not (isinstance(strike_count, (int, np.integer)) and isinstance(dip_count, (int, np.integer))
            and strike_count >= 1 and dip_count >= 2):
        raise InputError(f"a 3-D fault needs whole element counts, at least 1 along strike and 2 down dip, got "
                         f"{strike_count!r} x {dip_count!r}")
    if not (math.isfinite(element_size) and element_size > 0):
        raise InputError(f"a 3-D fault's element size must be a positive length, got {element_size!r}")
    if not (isinstance(dip, (int, float)) and 0.0 < dip <= 90.0):
        raise InputError(f"a 3-D fault's dip must lie in (0, 90] degrees, got {dip!r}")
    if rake not in RAKES:
        raise InputError(f"a 3-D fault slips along one of {', '.join(RAKES)}, got {rake!r}")
    if not 0.0 <= poisson_ratio < 0.5:
        raise InputError(f"Poisson's ratio must lie in [0, 0.5), got {poisson_ratio!r}")


class StrikeConvolution:
    """K applied by FFT along strike: ``operator(deficit)`` is the shear traction change of the slip deficit
    (N_x N_z, element (i, j) at i N_z + j), :meth:`both` that and the normal stress change stacked (N each).

    A vertical fault slipping along strike has no normal stress change (the dislocation's field is odd across the
    plane), and its normal kernel is left out; :attr:`normal_changes` says which.

    ``periodic_images``: make the fault periodic along strike with period N_x h instead, the kernel summed over
    that many images either side (K_per[d] = sum over |m| <= M of K[d + m N_x]). Slip uniform along strike then
    sees the 2-D fault's antiplane (or plane-strain) kernel, to the images' truncation: the exact 2-D limit of the
    3-D machinery, which a finite fault, its ends creeping, never reaches (docs/fault_3d.md).
    """

    method = "fft_strike"

    def __init__(self, strike_count: int, dip_count: int, element_size: float, dip: float = 90.0,
                 rake: str = "strike", shear_modulus: float = 3.2e10, poisson_ratio: float = 0.25,
                 periodic_images: int = 0):
        _check_grid(strike_count, dip_count, element_size, dip, rake, poisson_ratio)
        if not (isinstance(periodic_images, (int, np.integer)) and periodic_images >= 0):
            raise InputError(f"periodic_images must be a whole number of images, got {periodic_images!r}")
        self.strike_count, self.dip_count = int(strike_count), int(dip_count)
        self.count = self.strike_count * self.dip_count
        self.normal_changes = not (dip == 90.0 and rake == "strike")
        if periodic_images:
            reach = (2 * periodic_images + 1) * self.strike_count  # every offset the images need
            kernels = _row_kernels(reach, self.dip_count, element_size, dip, rake, shear_modulus, poisson_ratio)
            centre = reach - 1
            offsets = np.arange(self.strike_count)[:, None] + self.strike_count * np.arange(
                -periodic_images, periodic_images + 1)[None, :]
            shear, normal, cross = (kernel[centre + offsets].sum(axis=1) for kernel in kernels)
            self.length = self.strike_count  # the circular convolution is the periodic fault's own
            self.self_term = shear[0].diagonal().copy()
            self._spectra = [np.ascontiguousarray(np.fft.rfft(k, axis=0))
                             for k in ([shear, normal] if self.normal_changes else [shear])]
            self._cross = np.ascontiguousarray(np.fft.rfft(cross, axis=0))
            return
        shear, normal, cross = _row_kernels(self.strike_count, self.dip_count, element_size, dip, rake,
                                            shear_modulus, poisson_ratio)
        self.length = 2 * self.strike_count  # circular convolution of length 2 N_x holds the linear one
        self._spectra = [self._spectrum(shear)] + ([self._spectrum(normal)] if self.normal_changes else [])
        self._cross = self._spectrum(cross)
        self.self_term = shear[self.strike_count - 1].diagonal().copy()

    def _spectrum(self, kernel: np.ndarray) -> np.ndarray:
        # offsets -(N_x - 1)..N_x - 1 laid out circularly on 2 N_x points (index N_x left zero), transformed along
        # strike, then (frequency, observation row, source row) contiguous for the batched product
        circular = np.zeros((self.length, self.dip_count, self.dip_count))
        circular[: self.strike_count] = kernel[self.strike_count - 1:]
        circular[self.length - (self.strike_count - 1):] = kernel[: self.strike_count - 1]
        return np.ascontiguousarray(np.fft.rfft(circular, axis=0))

    @property
    def nbytes(self) -> int:
        """The product's memory (bytes): its spectra. The cross-rake spectrum (:meth:`cross`, a run's diagnostic)
        holds as many again as the shear one."""
        return sum(spectrum.nbytes for spectrum in self._spectra)

    def cross(self, slip: np.ndarray) -> np.ndarray:
        """The shear traction across the rake (:func:`cross_direction`) that ``slip`` causes (Pa): what a second
        slip component would answer, which the fixed rake leaves out."""
        transformed = np.fft.rfft(np.asarray(slip, float).reshape(self.strike_count, self.dip_count),
                                  n=self.length, axis=0)
        return self._apply(self._cross, transformed)

    def _apply(self, spectrum: np.ndarray, transformed: np.ndarray) -> np.ndarray:
        # numpy's own loop, not BLAS: OpenBLAS threads the batched product from about 80 squares down dip and its
        # threads spin between calls, doubling a run's CPU alone and crawling in a pool of one worker a core
        # (benchmarks/fault_3d_resolution.py's 25 m runs); one thread, the same CPU as BLAS held to one
        product = np.einsum("kij,kj->ki", spectrum, transformed)
        return np.fft.irfft(product, n=self.length, axis=0)[: self.strike_count].reshape(-1)

    def both(self, deficit: np.ndarray) -> np.ndarray:
        """(shear change, normal change) stacked, N each (Pa); the normal part is zero where it has none."""
        transformed = np.fft.rfft(np.asarray(deficit, float).reshape(self.strike_count, self.dip_count),
                                  n=self.length, axis=0)
        shear = self._apply(self._spectra[0], transformed)
        normal = self._apply(self._spectra[1], transformed) if self.normal_changes else np.zeros(self.count)
        return np.concatenate([shear, normal])

    def __call__(self, deficit: np.ndarray) -> np.ndarray:
        transformed = np.fft.rfft(np.asarray(deficit, float).reshape(self.strike_count, self.dip_count),
                                  n=self.length, axis=0)
        return self._apply(self._spectra[0], transformed)
