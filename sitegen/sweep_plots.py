"""The plots of a sweep page: a scatter of two columns and a histogram of the ranking key, as
inline SVG whose colours are the theme's CSS variables (``--fg``, ``--muted``, ``--line``,
``--accent``), so one figure reads in the light and the dark theme.

Written here rather than with a plotting library: two small fixed figures, a few dozen lines of
SVG with the page's own colours; matplotlib would add a large dependency and fixed colours.
Every text is escaped; numbers are rounded so the same results give the same bytes.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from html import escape

W, H = 420, 300
LEFT, RIGHT, TOP, BOTTOM = 58, 14, 14, 44
FG = "fill:var(--fg,#1f2328)"
MUTED = "var(--muted,#59636e)"
LINE = "var(--line,#d1d9e0)"
ACCENT = "var(--accent,#0b5cad)"


def _ticks(lo: float, hi: float, n: int = 5) -> list[float]:
    if hi <= lo:
        return [lo]
    step = 10 ** math.floor(math.log10((hi - lo) / n))
    for m in (1, 2, 5, 10):
        if (hi - lo) / (step * m) <= n:
            step *= m
            break
    first = math.ceil(lo / step) * step
    return [round(first + i * step, 12) for i in range(int((hi - first) / step + 1e-9) + 1)]


def _span(values: Sequence[float]) -> tuple[float, float]:
    lo, hi = min(values), max(values)
    if hi - lo < 1e-12:
        lo, hi = lo - 0.5, hi + 0.5
    pad = (hi - lo) * 0.05
    return lo - pad, hi + pad


def _num(v: float) -> str:
    return f"{v:.6g}"


class _Axes:
    """Data to pixel mapping of one plot's frame."""

    def __init__(self, xs: tuple[float, float], ys: tuple[float, float]):
        (self.x0, self.x1), (self.y0, self.y1) = xs, ys
        self.pw, self.ph = W - LEFT - RIGHT, H - TOP - BOTTOM

    def px(self, x: float) -> float:
        return LEFT + (x - self.x0) / (self.x1 - self.x0) * self.pw

    def py(self, y: float) -> float:
        return TOP + self.ph - (y - self.y0) / (self.y1 - self.y0) * self.ph


def _frame(title: str, xlabel: str, ylabel: str, ax: _Axes, body: list[str]) -> str:
    pw, ph = ax.pw, ax.ph
    out = [
        f'<svg class="sweep-plot" xmlns="http://www.w3.org/2000/svg" viewBox="0 0 {W} {H}" '
        f'role="img" aria-label="{escape(title)}" style="max-width:100%;height:auto;'
        'font:11px system-ui,sans-serif">',
        f"<title>{escape(title)}</title>",
        f'<rect x="{LEFT}" y="{TOP}" width="{pw}" height="{ph}" style="fill:none;stroke:{LINE}"/>',
    ]
    for t in _ticks(ax.x0, ax.x1):
        x = ax.px(t)
        out.append(f'<line x1="{x:.1f}" y1="{TOP}" x2="{x:.1f}" y2="{TOP + ph}" '
                   f'style="stroke:{LINE};stroke-width:.5"/>')  # fmt: skip
        out.append(f'<text x="{x:.1f}" y="{TOP + ph + 14}" text-anchor="middle" '
                   f'style="{FG}">{_num(t)}</text>')  # fmt: skip
    for t in _ticks(ax.y0, ax.y1):
        y = ax.py(t)
        out.append(f'<line x1="{LEFT}" y1="{y:.1f}" x2="{LEFT + pw}" y2="{y:.1f}" '
                   f'style="stroke:{LINE};stroke-width:.5"/>')  # fmt: skip
        out.append(f'<text x="{LEFT - 4}" y="{y + 4:.1f}" text-anchor="end" '
                   f'style="{FG}">{_num(t)}</text>')  # fmt: skip
    out.append(f'<text x="{LEFT + pw / 2:.1f}" y="{H - 8}" text-anchor="middle" '
               f'style="{FG}">{escape(xlabel)}</text>')  # fmt: skip
    out.append(f'<text transform="translate(12 {TOP + ph / 2:.1f}) rotate(-90)" '
               f'text-anchor="middle" style="{FG}">{escape(ylabel)}</text>')  # fmt: skip
    out += body
    out.append("</svg>")
    return "\n".join(out)


def scatter(
    points: Sequence[tuple[int, float, float]], best: set[int], title: str, xl: str, yl: str
) -> str:
    """``points``: (run index, x, y); the best runs are drawn in the accent colour."""
    if not points:
        return ""
    ax = _Axes(_span([p[1] for p in points]), _span([p[2] for p in points]))
    body = []
    for index, x, y in sorted(points, key=lambda p: (p[0] in best, p[0])):
        style = f"fill:{ACCENT}" if index in best else f"fill:{MUTED};fill-opacity:.55"
        r = 5 if index in best else 3
        body.append(
            f'<circle cx="{ax.px(x):.1f}" cy="{ax.py(y):.1f}" r="{r}" style="{style}">'
            f"<title>run {index}: {_num(x)}, {_num(y)}</title></circle>"
        )
    return _frame(title, xl, yl, ax, body)


def histogram(
    values: Sequence[float], title: str, label: str, ylabel: str = "runs", bins: int = 20
) -> str:
    if not values:
        return ""
    lo, hi = min(values), max(values)
    if hi - lo < 1e-12:
        lo, hi = lo - 0.5, hi + 0.5
    width = (hi - lo) / bins
    counts = [0] * bins
    for v in values:
        counts[min(bins - 1, int((v - lo) / width))] += 1
    ax = _Axes((lo, hi), (0.0, max(counts) * 1.08))
    body = []
    for i, n in enumerate(counts):
        if n:
            a, b = lo + i * width, lo + (i + 1) * width
            x, y = ax.px(a), ax.py(n)
            body.append(
                f'<rect x="{x:.1f}" y="{y:.1f}" width="{max(0.5, ax.px(b) - x - 1):.1f}" '
                f'height="{ax.py(0.0) - y:.1f}" style="fill:{ACCENT};fill-opacity:.8">'
                f"<title>{_num(a)} – {_num(b)}: {n}</title></rect>"
            )
    return _frame(title, label, ylabel, ax, body)
