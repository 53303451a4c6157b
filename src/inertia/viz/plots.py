"""Static figures (matplotlib, Agg backend, imported lazily), each saved as PNG and SVG.

Every function returns the data it drew that a reader may want to check (for example the
flip times it marked), so tests compare pictures with the library's numbers, not pixels.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from .._core.optional import require


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


def omega_plot(study, out_dir, stem: str = "omega") -> dict:
    """Body angular velocity components against time, predicted flip times marked."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 3.6))
    for k, name in enumerate(("about axis 1 (minor)", "about axis 2 (intermediate)", "about axis 3 (major)")):
        ax.plot(study.t, study.omega_exact[:, k], label=f"omega {k + 1}, {name}", lw=1.4)
    marked = [float(x) for x in study.flip_times if x <= study.t[-1]]
    for i, tf in enumerate(marked):
        ax.axvline(tf, color="0.4", ls="--", lw=0.8, label="predicted flip (2K(m)/lambda apart)" if i == 0 else None)
    ax.set_xlabel("t [s]")
    ax.set_ylabel("omega_body [rad/s]")
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
    """Polhodes on the angular-momentum sphere |m| = |L|: level curves of the energy, the
    separatrix (energy 2E = |L|^2/I2) in red, the demo's own path in black."""
    plt = pyplot()
    I = study.moments
    G = float(np.linalg.norm(I * study.omega0_body))
    fig = plt.figure(figsize=(5.2, 5.2))
    ax = fig.add_subplot(projection="3d")
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, 60), np.linspace(0, np.pi, 30))
    ax.plot_surface(G * np.cos(u) * np.sin(v), G * np.sin(u) * np.sin(v), G * np.cos(v), color="0.9", alpha=0.25,
                    linewidth=0)
    # polhodes: m(t) for a fan of initial conditions on the sphere, via the exact solution
    from ..dynamics.exact import exact_solution

    for a in np.linspace(0.15, 1.45, 6):
        for sign in (1, -1):
            for axis in (0, 2):
                m0 = np.zeros(3)
                m0[axis] = sign * G * np.cos(a)
                m0[1] = G * np.sin(a)
                w0 = m0 / I
                try:
                    _, w = exact_solution(I, w0, np.linspace(0, 40 / max(np.linalg.norm(w0), 1e-12), 400))
                except Exception:  # noqa: BLE001 - a fan member on the separatrix: skip it
                    continue
                m = w * I
                ax.plot(m[:, 0], m[:, 1], m[:, 2], color="tab:blue", lw=0.6, alpha=0.7)
    # the separatrix (2E = G^2/I2) on the sphere: the two curves m3 = +-c m1 through +-e2,
    # with c^2 = (1/I1 - 1/I2) / (1/I2 - 1/I3)
    th = np.linspace(0, 2 * np.pi, 400)
    c = np.sqrt((1 / I[0] - 1 / I[1]) / (1 / I[1] - 1 / I[2]))
    for s in (1, -1):
        m1 = G * np.cos(th) / np.sqrt(1 + c**2)
        ax.plot(m1, G * np.sin(th), s * c * m1, color="tab:red", lw=2.2, label="separatrix" if s == 1 else None)
    m = study.omega_exact * I
    # dashed and thinner: this spin runs next to the separatrix and would hide it
    ax.plot(m[:, 0], m[:, 1], m[:, 2], color="k", lw=1.0, ls="--", label="this spin")
    labels = ("m1 [kg m^2/s]", "m2 [kg m^2/s]", "m3 [kg m^2/s]")
    files = _finish_3d(plt, fig, ax, labels, "Polhodes on the angular-momentum sphere", 7, out_dir, stem)
    return {"files": files}


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


def body_plot(props, six, out_dir, stem: str = "body") -> dict:
    """The body's principal axes and six point masses to scale, with the equivalent box."""
    plt = pyplot()
    from ..massprops.equivalent import equivalent_box

    moments, R = props.principal()
    c = props.com
    fig = plt.figure(figsize=(5.2, 5.2))
    ax = fig.add_subplot(projection="3d")
    box = equivalent_box(props)
    corners, edges = box_wire(np.asarray(box.size) / 2)
    world = corners @ R.T + c
    for i, j in edges:
        ax.plot(*zip(world[i], world[j]), color="0.6", lw=0.8)
    pts = six.positions_body
    ax.scatter(pts[:, 0], pts[:, 1], pts[:, 2], s=40, color="tab:orange", label="six point masses (M/6 each)")
    colors = ("tab:red", "tab:green", "tab:blue")
    span = float(np.max(np.abs(pts - c))) * 1.3
    for k in range(3):
        end = c + span * R[:, k]
        ax.plot(*zip(c, end), color=colors[k], lw=2, label=f"principal axis {k + 1}: I = {moments[k]:.4g} kg m^2")
    lim = span * 1.1
    ax.set_xlim(c[0] - lim, c[0] + lim)
    ax.set_ylim(c[1] - lim, c[1] + lim)
    ax.set_zlim(c[2] - lim, c[2] + lim)
    files = _finish_3d(plt, fig, ax, ("x [m]", "y [m]", "z [m]"),
                       "Principal axes, six-point model and equivalent box", 6, out_dir, stem)
    return {"files": files, "points": pts.tolist()}
