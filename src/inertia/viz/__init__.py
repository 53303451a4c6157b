"""Pictures of a body and its motion: the report folder (plots, the 3D page, the flip film),
the control showcase, and the pieces they are built from.

Matplotlib, Pillow and the video writer are imported only when a name is used
(``pip install "inertia[viz]"``); ``import inertia.viz`` loads no NumPy.
"""

from __future__ import annotations

from .._core.lazy import lazy_namespace

# public name -> submodule that defines it
_EXPORTS = {
    # whole outputs
    "build_report": "report", "write_control": "control_report", "page_data": "page", "write_page": "page",
    # the mesh shown and the films
    "display_mesh": "display_mesh", "DisplayMesh": "display_mesh", "FlipScene": "animation",
    "render_flip": "animation", "render_hold": "control_animation", "video_format": "animation",
    # figures
    "omega_plot": "plots", "invariants_plot": "plots", "polhode_plot": "plots", "body_plot": "plots",
    "passive_plot": "control_plots", "active_plot": "control_plots", "monte_carlo_plot": "control_plots",
}

__getattr__, __dir__, __all__ = lazy_namespace(__name__, _EXPORTS, ())
