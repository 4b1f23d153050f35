"""Shaded-tube pictures of a rod, as in the paper's Figs 3, 4 and 6.

The tube surface at fiducial s is the circle r(s) + rho (cos phi d1 + sin phi d2): the
cross-section disk of Sec 2 oriented by the directors, so shear (d3 not along the
tangent) shows as tilted rings, bend as curvature of the centerline and twist as the
stripe drawn along d1 (the paper's "dark line").
"""
from __future__ import annotations

import numpy as np


def tube_surface(centerline: np.ndarray, directors: np.ndarray, radius: float, n_phi: int = 24):
    """X, Y, Z (N, n_phi + 1) of the tube around centerline (N, 3) with directors (N, 3, 3)."""
    phi = np.linspace(0.0, 2.0 * np.pi, n_phi + 1)
    d1, d2 = directors[:, :, 0], directors[:, :, 1]
    pts = (centerline[:, None, :] + radius * (np.cos(phi)[None, :, None] * d1[:, None, :]
                                             + np.sin(phi)[None, :, None] * d2[:, None, :]))
    return pts[..., 0], pts[..., 1], pts[..., 2]


def close_periodic(centerline, directors, Gamma, s):
    """Append the point s = L: r(L) = r(0) + P with P = int T Gamma ds (trapezoid, periodic)
    and the same directors as s = 0 for a rod whose frame closes (approximately)."""
    ds = s[1] - s[0]
    P = np.einsum("ixk,ik->x", directors, Gamma) * ds
    return (np.vstack([centerline, centerline[:1] + P]),
            np.concatenate([directors, directors[:1]], axis=0))


def draw_tube(ax, centerline, directors, radius: float, color="#9db8d9", n_phi: int = 24,
              rings_every: int = 8, stripe: bool = True):
    """Draw one shaded tube on a 3D axes, with cross-section rings and a d1 stripe."""
    from matplotlib.colors import LightSource
    X, Y, Z = tube_surface(centerline, directors, radius, n_phi)
    ls = LightSource(azdeg=315, altdeg=45)
    ax.plot_surface(X, Y, Z, color=color, shade=True, lightsource=ls, linewidth=0,
                    antialiased=False, rstride=1, cstride=1, alpha=1.0)
    if rings_every:
        for i in range(0, len(centerline), rings_every):
            ax.plot(X[i], Y[i], Z[i], color="k", lw=0.6, zorder=9)
    if stripe:
        line = centerline + 1.03 * radius * directors[:, :, 0]
        ax.plot(line[:, 0], line[:, 1], line[:, 2], color="#b00000", lw=1.4, zorder=10)


def axis_rotation(frames) -> np.ndarray:
    """Rotation Q (3 x 3) taking the mean rod direction of the first frame to lab x, so
    the rod lies horizontally as in the paper's figures (applied as Q @ v)."""
    c = frames[0][0]
    a = c[-1] - c[0]
    a = a / np.linalg.norm(a)
    helper = np.array([0.0, 0.0, 1.0]) if abs(a[2]) < 0.9 else np.array([0.0, 1.0, 0.0])
    b = np.cross(helper, a)
    b /= np.linalg.norm(b)
    return np.vstack([a, b, np.cross(a, b)])


def set_equal_box(ax, points: np.ndarray, pad: float = 0.0, zoom: float = 1.0):
    """Equal scale on the three axes, box just around points (M, 3)."""
    lo, hi = points.min(axis=0) - pad, points.max(axis=0) + pad
    ax.set_xlim(lo[0], hi[0])
    ax.set_ylim(lo[1], hi[1])
    ax.set_zlim(lo[2], hi[2])
    ax.set_box_aspect(tuple(np.maximum(hi - lo, 1e-9)), zoom=zoom)


def snapshot_figure(path, frames, radius: float, titles, view=(25, -80), dpi: int = 80,
                    suptitle: str | None = None, rings_every: int = 8):
    """Tube snapshots stacked top to bottom in one 3D scene (as in the paper), frames =
    [(centerline, directors), ...] in the lab frame, rotated together so that the rod
    axis is horizontal; each snapshot is re-centred and shifted down by a fixed gap."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    Q = axis_rotation(frames)
    frames = [(c @ Q.T, np.einsum("ab,ibk->iak", Q, d)) for c, d in frames]
    n = len(frames)
    length = max(np.ptp(c[:, 0]) for c, _ in frames)
    height = max(np.ptp(c[:, 2]) for c, _ in frames) + 2 * radius
    gap = max(height * 1.4, 0.8 * length / n)
    fig = plt.figure(figsize=(6.5, 4.6))
    ax = fig.add_axes([0.0, 0.0, 1.0, 0.95], projection="3d")
    pts = []
    for j, ((c, d), title) in enumerate(zip(frames, titles)):
        shift = -(c.min(axis=0) + c.max(axis=0)) / 2 + np.array([0.0, 0.0, -j * gap])
        c = c + shift
        draw_tube(ax, c, d, radius, rings_every=rings_every)
        ax.text(c[:, 0].min() - 0.12 * length, 0.0, -j * gap, title, fontsize=8, ha="right")
        pts.append(c)
    pts = np.concatenate(pts)
    set_equal_box(ax, np.vstack([pts, pts[:1] - np.array([0.3 * length, 0, 0])]), pad=1.5 * radius, zoom=1.0)
    ax.view_init(*view)
    ax.set_axis_off()
    if suptitle:
        fig.suptitle(suptitle, fontsize=10)
    fig.savefig(path, dpi=dpi)
    plt.close(fig)
