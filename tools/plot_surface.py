#!/usr/bin/python3
"""A height map with its radially averaged PSD and the fitted Hurst exponent.

usage: tools/plot_surface.py FILE --length L [--periodic] [--out FILE.png]
       tools/plot_surface.py RUN_DIR [--which initial|final] [--out FILE.png]

FILE is what `fretbem surface --out FILE` wrote (.h5 dataset `height`, .npy, or text with rows
along y); L is the side of the domain along x in m (grid.length). RUN_DIR is a run's folder:
the surface and the grid come from its result.h5. The PSD follows surface/statistics.cpp:
C(q) with sum C (2 pi)^2 / A = <z^2>, rings of width 2 pi / L, a Hann window on free (not
periodic) grids, and H from the least-squares slope -2(1 + H) of log C over
4 (2 pi / L) <= q <= q_Nyquist / 4. Writes FILE.png and FILE.pdf.
"""
import argparse
import os

import numpy as np

import fretbem_plot as fp

TOOL = "plot_surface"


def load(path, which):
    if os.path.isdir(path):
        scn = fp.read_scenario(path)
        with fp.open_h5(os.path.join(path, "result.h5"), TOOL) as f:
            z = np.asarray(f[f"surface/{which}"], dtype=float)
        return z, fp.number(scn, "grid.length"), scn.get("grid.periodic") == "true"
    ext = os.path.splitext(path)[1].lower()
    if ext in (".h5", ".hdf5"):
        with fp.open_h5(path, TOOL) as f:
            return np.asarray(f["height"], dtype=float), None, None
    if ext == ".npy":
        return np.load(path).astype(float), None, None
    return np.loadtxt(path, ndmin=2), None, None


def radial_psd(z, length, periodic):
    ny, nx = z.shape
    h = length / nx
    z = z - z.mean()
    if not periodic:  # Hann window normalised to mean(w^2) = 1
        w = np.outer(np.hanning(ny + 2)[1:-1], np.hanning(nx + 2)[1:-1])
        z = z * w / np.sqrt(np.mean(w**2))
    area = nx * ny * h * h
    c = np.abs(np.fft.fft2(z)) ** 2 * h**4 / area
    qx = 2 * np.pi * np.fft.fftfreq(nx, d=h)
    qy = 2 * np.pi * np.fft.fftfreq(ny, d=h)
    q = np.hypot(*np.meshgrid(qx, qy))
    dq = 2 * np.pi / min(nx * h, ny * h)
    ring = np.floor(q / dq + 0.5).astype(int)
    rings = np.arange(1, ring.max() + 1)
    qm = np.array([q[ring == r].mean() for r in rings])
    cm = np.array([c[ring == r].mean() for r in rings])
    return qm, cm, dq, np.pi / h


def fit_hurst(q, c, dq, q_nyquist):
    sel = (q >= 4 * dq) & (q <= q_nyquist / 4) & (c > 0)
    if sel.sum() < 3:
        return float("nan"), sel
    slope = np.polyfit(np.log(q[sel]), np.log(c[sel]), 1)[0]
    return -0.5 * slope - 1, sel


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("source", help="height-map file or run folder")
    ap.add_argument("--length", type=float, default=None, help="domain side along x (m)")
    ap.add_argument("--periodic", action="store_true", help="the map is periodic (no window)")
    ap.add_argument("--which", default="initial", choices=("initial", "final"))
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    if not os.path.exists(a.source):
        fp.fail(TOOL, f"{a.source}: not found")
    z, length, periodic = load(a.source, a.which)
    length = a.length or length
    if not length:
        fp.fail(TOOL, "--length: give the domain side along x in m (grid.length)")
    periodic = a.periodic or bool(periodic)
    ny, nx = z.shape
    q, c, dq, qn = radial_psd(z, length, periodic)
    hurst, sel = fit_hurst(q, c, dq, qn)
    fig, ax = fp.figure(ncols=2, width=3.5, height=3.0)
    half = 0.5 * length * 1e6
    ax[0][0].grid(False)
    im = ax[0][0].imshow((z - z.mean()) * 1e6, origin="lower", cmap="terrain",
                         extent=[-half, half, -half * ny / nx, half * ny / nx])
    fig.colorbar(im, ax=ax[0][0], shrink=0.85, label="height z (µm)")
    rms = np.sqrt(np.mean((z - z.mean()) ** 2))
    ax[0][0].set(xlabel="x (µm)", ylabel="y (µm)",
                 title=f"{nx} × {ny}, rms height {rms * 1e9:.4g} nm")
    ax[0][1].loglog(q, c, ".", ms=3, color="0.5", label="radial PSD")
    if np.isfinite(hurst):
        k = np.polyfit(np.log(q[sel]), np.log(c[sel]), 1)
        ax[0][1].loglog(q[sel], np.exp(np.polyval(k, np.log(q[sel]))), "r-",
                        label=f"fit: H = {hurst:.3f}")
    ax[0][1].set(xlabel="wavenumber q (1/m)", ylabel="C(q) (m⁴)", title="power spectral density")
    ax[0][1].legend(frameon=False)
    out = a.out or (os.path.join(a.source, "surface.png") if os.path.isdir(a.source)
                    else os.path.splitext(a.source)[0] + ".png")
    fp.save(fig, out)


if __name__ == "__main__":
    fp.guarded(main, TOOL)
