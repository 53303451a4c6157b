"""Static figures (matplotlib, Agg backend, imported lazily), each saved as PNG and SVG.

Every function returns the data it drew that a reader may want to check (for example the
flip times it marked), so tests compare pictures with the library's numbers, not pixels.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .._core.optional import require

#: colours of principal axes 1, 2, 3 and of the separatrix in every picture (plots, video, 3D page)
AXIS_COLORS = ("#d9534f", "#3aa76d", "#3b82f6")
SEPARATRIX = "#9b59d0"


def pyplot():
    matplotlib = require("matplotlib", "plots")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def box_wire(half):
    """Corners (8, 3) of a box with half-extents ``half`` and its 12 edges as corner-index pairs."""
    from ..geometry.shapes import BOX_CORNER_SIGNS, box_edges

    return BOX_CORNER_SIGNS * np.asarray(half, float), box_edges()


def _save(fig, out_dir: Path, stem: str) -> list[str]:
    from .._core.atomic import write_bytes_atomic

    names = []
    for ext in ("png", "svg"):
        import io

        buf = io.BytesIO()
        # mplot3d projects its padded face arrays, whose masked padding is uninitialised memory
        # (it silences invalid and divide there, not overflow): a RuntimeWarning about nothing
        # drawn, whose appearance depends on what the memory held before
        with np.errstate(over="ignore"):
            fig.savefig(buf, format=ext, dpi=110, bbox_inches="tight")
        write_bytes_atomic(out_dir / f"{stem}.{ext}", buf.getvalue())
        names.append(f"{stem}.{ext}")
    return names


#: the figure writer, for the other figure modules (viz.control_plots)
save_figure = _save


def omega_plot(study, out_dir, stem: str = "omega") -> dict:
    """Body angular velocity components against time, predicted flip times marked."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 3.6))
    for k, name in enumerate(("about axis 1 (minor)", "about axis 2 (intermediate)", "about axis 3 (major)")):
        ax.plot(study.t, study.omega_exact[:, k], label=f"$\\omega_{k + 1}$ {name}", lw=1.4, color=AXIS_COLORS[k])
    marked = [float(x) for x in study.flip_times if x <= study.t[-1]]
    for i, tf in enumerate(marked):
        ax.axvline(tf, color="0.4", ls="--", lw=0.8,
                   label="predicted flip ($2K(m)/\\lambda$ apart)" if i == 0 else None)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("$\\omega$, body frame [rad/s]")
    ax.set_title(f"Spin about the intermediate axis: a flip every {study.flip_interval:.4g} s (exact solution)")
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.01, 1.0))  # outside: the curves fill the axes
    ax.grid(alpha=0.3)
    files = _save(fig, Path(out_dir), stem)
    plt.close(fig)
    return {"files": files, "flip_times": marked, "flip_interval": float(study.flip_interval)}


def invariants_plot(study, out_dir, stem: str = "invariants") -> dict:
    """Relative energy and |L| error of each integrator against time (log scale)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 3.6))
    floor = 1e-17
    for name, tr in study.integrators.items():
        ax.semilogy(tr["t"], np.maximum(tr["energy_error"], floor), label=f"{name}: energy", lw=1.2)
        ax.semilogy(tr["t"], np.maximum(tr["momentum_error"], floor), ls=":", label=f"{name}: |L|", lw=1.2)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("relative error")
    h = next(iter(study.integrators.values()))["h"]
    ax.set_title(f"Invariants at h = {h:.3g} s (errors below 1e-17 drawn at 1e-17)")
    ax.legend(fontsize=7, ncol=2)
    ax.grid(alpha=0.3, which="both")
    files = _save(fig, Path(out_dir), stem)
    plt.close(fig)
    return {"files": files, "max_errors": {k: {"energy": float(v["energy_error"].max()),
                                               "momentum": float(v["momentum_error"].max())}
                                           for k, v in study.integrators.items()}}


def polhode_plot(study, out_dir, stem: str = "polhodes") -> dict:
    """Polhodes on the angular-momentum sphere |m| = |L| (principal axes): level curves of the
    energy (:mod:`.polhodes`), the separatrix through the intermediate axis, this spin's path.
    Axes in a power of ten of kg m^2/s, three ticks each, so no tick labels collide."""
    from . import polhodes

    plt = pyplot()
    I = study.moments
    G = float(np.linalg.norm(I * study.omega0_body))
    exponent = int(np.floor(np.log10(G)))
    g = G / 10.0 ** exponent                       # the sphere's radius in the axis unit
    fig = plt.figure(figsize=(5.6, 5.4))
    ax = fig.add_subplot(projection="3d")
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 60), np.linspace(0, np.pi, 30))
    ax.plot_surface(g * np.cos(u) * np.sin(v), g * np.sin(u) * np.sin(v), g * np.cos(v), color="0.9", alpha=0.25,
                    linewidth=0)
    for k, c in enumerate(polhodes.fan(I)):
        ax.plot(*(g * c).T, color="tab:blue", lw=0.6, alpha=0.7, label="other energies" if k == 0 else None)
    for k, c in enumerate(polhodes.separatrix(I)):
        ax.plot(*(g * c).T, color=SEPARATRIX, lw=2.2, label="separatrix" if k == 0 else None)
    # dashed and thinner: this spin runs next to the separatrix and would hide it
    ax.plot(*(g * polhodes.path(study)).T, color="k", lw=1.0, ls="--", label="this spin")
    tick = float(f"{0.8 * g:.1g}")
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.set_ticks([-tick, 0.0, tick])
    ax.set(xlim=(-g, g), ylim=(-g, g), zlim=(-g, g))
    unit = f"[$10^{{{exponent}}}$ kg m$^2$/s]" if exponent else "[kg m$^2$/s]"
    labels = tuple(f"$m_{k}$ {unit}" for k in (1, 2, 3))
    files = _finish_3d(plt, fig, ax, labels, "Polhodes on the angular-momentum sphere", 7, out_dir, stem)
    return {"files": files, "axis_unit_exponent": exponent}


def _finish_3d(plt, fig, ax, labels, title: str, legend_size: int, out_dir, stem: str) -> list:
    """Equal aspect, axis labels, title and legend of a 3D figure; saved (PNG, SVG) and closed."""
    ax.set_box_aspect((1, 1, 1))
    for set_label, text in zip((ax.set_xlabel, ax.set_ylabel, ax.set_zlabel), labels):
        set_label(text)
    ax.set_title(title)
    ax.legend(fontsize=legend_size, loc="upper left")
    files = _save(fig, Path(out_dir), stem)
    plt.close(fig)
    return files


def body_plot(props, six, out_dir, stem: str = "body", display=None) -> dict:
    """The body (its display mesh, shaded), its principal axes, the six point masses and the
    equivalent box, to scale, in the body frame (lengths in mm below half a metre)."""
    plt = pyplot()
    from ..massprops.equivalent import equivalent_box
    from .display_mesh import cluster_decimate
    from .page import length_unit

    pf = props.principal()
    moments, R, c = pf.moments, pf.R_body_principal, props.com
    pts = six.positions_body
    span = float(np.max(np.abs(pts - c))) * 1.3
    if display is not None:
        span = max(span, 1.1 * display.radius)
    unit, f = length_unit(span)
    fig = plt.figure(figsize=(5.6, 5.4))
    ax = fig.add_subplot(projection="3d")
    if display is not None:
        V, F = cluster_decimate(display.vertices, display.faces, 1500)
        _draw_mesh(ax, f * (V @ R.T + c), F)
    box = equivalent_box(props)
    corners, edges = box_wire(np.asarray(box.size) / 2)
    world = f * (corners @ R.T + c)
    for i, j in edges:
        ax.plot(*zip(world[i], world[j]), color="0.45", lw=0.8, label="equivalent box" if (i, j) == edges[0] else None)
    ax.scatter(*(f * pts).T, s=40, color="tab:orange", depthshade=False, label="six point masses (M/6 each)")
    for k in range(3):
        ax.plot(*zip(f * c, f * (c + span * R[:, k])), color=AXIS_COLORS[k], lw=2,
                label=f"principal axis {k + 1}: I = {moments[k]:.4g} kg m$^2$")
    lim = f * span * 1.1
    ax.set(xlim=(f * c[0] - lim, f * c[0] + lim), ylim=(f * c[1] - lim, f * c[1] + lim),
           zlim=(f * c[2] - lim, f * c[2] + lim))
    for axis in (ax.xaxis, ax.yaxis, ax.zaxis):
        axis.set_major_locator(_max_ticks(4))
    title = "The body, principal axes, six points and equivalent box" if display is not None else \
        "Principal axes, six-point model and equivalent box"
    files = _finish_3d(plt, fig, ax, tuple(f"{a} [{unit}] (body frame)" for a in "xyz"), title, 6, out_dir, stem)
    return {"files": files, "points": pts.tolist(), "length_unit": unit}


def _max_ticks(n: int):
    from matplotlib.ticker import MaxNLocator

    return MaxNLocator(nbins=n)


def _draw_mesh(ax, V, F) -> None:
    """A shaded, slightly transparent triangle mesh (lit from the upper left, flat per face)."""
    from mpl_toolkits.mplot3d.art3d import Poly3DCollection

    tri = V[F]
    n = np.cross(tri[:, 1] - tri[:, 0], tri[:, 2] - tri[:, 0])
    n /= np.maximum(np.linalg.norm(n, axis=1, keepdims=True), 1e-300)
    light = np.array([-0.4, -0.5, 0.75]) / np.linalg.norm([-0.4, -0.5, 0.75])
    shade = 0.35 + 0.65 * np.abs(n @ light)
    rgb = np.array([0.62, 0.67, 0.74])[None] * shade[:, None]
    coll = Poly3DCollection(tri, facecolors=np.column_stack([rgb, np.full(len(F), 0.55)]), edgecolors="none")
    coll.set_label("the body")
    ax.add_collection3d(coll)
