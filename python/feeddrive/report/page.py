"""A small HTML page of sections: text, tables and PNG figures (matplotlib, Agg)."""

from __future__ import annotations

import html
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt


class Page:
    """Collects sections and writes ``index.html`` plus PNGs into one folder."""

    def __init__(self, out_dir: str | Path, title: str) -> None:
        self.dir = Path(out_dir)
        self.dir.mkdir(parents=True, exist_ok=True)
        self.title = title
        self.parts: list[str] = []

    def heading(self, text: str, level: int = 2) -> None:
        self.parts.append(f"<h{level}>{html.escape(text)}</h{level}>")

    def text(self, text: str) -> None:
        self.parts.append(f"<p>{html.escape(text)}</p>")

    def pre(self, text: str) -> None:
        self.parts.append(f"<pre>{html.escape(text)}</pre>")

    def lines(self, lines: Sequence[str]) -> None:
        """One paragraph of lines (escaped), separated by line breaks."""
        if lines:
            self.parts.append("<p>" + "<br>".join(html.escape(t) for t in lines) + "</p>")

    def cells(self, header: Sequence[str], rows: Sequence[Sequence[Sequence[str]]]) -> None:
        """A table whose cells hold several lines each (escaped; the first may be bold)."""
        head = "".join(f"<th>{html.escape(c)}</th>" for c in header)
        body = "".join(
            "<tr>"
            + "".join(
                "<td style='text-align:left;vertical-align:top'>"
                + "<br>".join(html.escape(t) for t in cell)
                + "</td>"
                for cell in row
            )
            + "</tr>"
            for row in rows
        )
        self.parts.append(f"<table><tr>{head}</tr>{body}</table>")

    def table(self, rows: Sequence[dict[str, Any]], caption: str = "", digits: int = 3) -> None:
        if not rows:
            return
        cols = list(rows[0].keys())

        def fmt(v: Any) -> str:
            if isinstance(v, float):
                return f"{v:.{digits}g}" if abs(v) < 1e4 else f"{v:.4g}"
            return html.escape(str(v))

        head = "".join(f"<th>{html.escape(c)}</th>" for c in cols)
        body = "".join(
            "<tr>" + "".join(f"<td>{fmt(r.get(c, ''))}</td>" for c in cols) + "</tr>" for r in rows
        )
        cap = f"<caption>{html.escape(caption)}</caption>" if caption else ""
        self.parts.append(f"<table>{cap}<tr>{head}</tr>{body}</table>")

    def figure(self, fig: plt.Figure, name: str, caption: str = "", dpi: int = 110) -> Path:
        """Save ``fig`` as ``name``.png beside the page and show it with ``caption``."""
        path = self.dir / f"{name}.png"
        fig.savefig(path, dpi=dpi, bbox_inches="tight")
        plt.close(fig)
        self.parts.append(
            f'<figure><img src="{path.name}" alt="{html.escape(name)}">'
            f"<figcaption>{html.escape(caption)}</figcaption></figure>"
        )
        return path

    def write(self, name: str = "index.html") -> Path:
        """Write the page as ``name`` in the page's folder; returns its path."""
        style = (
            "body{font-family:sans-serif;max-width:1100px;margin:auto}"
            "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #999;"
            "padding:2px 8px;text-align:right}caption{font-weight:bold}"
            "img{max-width:100%}figure{margin:1em 0}"
            "pre{white-space:pre-wrap;overflow-wrap:anywhere}"
        )
        doc = (
            f"<!DOCTYPE html><html><head><meta charset='utf-8'><title>{html.escape(self.title)}"
            f"</title><style>{style}</style></head><body><h1>{html.escape(self.title)}</h1>"
            + "\n".join(self.parts)
            + "</body></html>"
        )
        path = self.dir / name
        path.write_text(doc, encoding="utf-8")
        return path
