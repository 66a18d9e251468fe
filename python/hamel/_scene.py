"""A run's 3D scene: one self-contained HTML page (three.js embedded, no network), shown
inline in Jupyter."""

from __future__ import annotations

import html


class Scene:
    """The scene of a run (``model.scene(run)``): shown inline in Jupyter, ``save(path)``
    writes the page, ``html`` is its text."""

    def __init__(self, page: str, height: int = 520):
        self.html = page
        self.height = height

    def _repr_html_(self) -> str:
        # The page is a whole document with its own scripts: an iframe keeps it apart from
        # the notebook's page.
        return (f'<iframe srcdoc="{html.escape(self.html, quote=True)}" '
                f'style="width: 100%; height: {self.height}px; border: 0" '
                f'sandbox="allow-scripts"></iframe>')

    def save(self, path) -> None:
        with open(path, "w", encoding="utf-8") as f:
            f.write(self.html)

    def __repr__(self) -> str:
        return f"<hamel.Scene: {len(self.html) / 1e6:.2f} MB page>"
