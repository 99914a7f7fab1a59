"""The x-y path of the robot body as a small, dependency-free, deterministic SVG.

Drawn by hand (no matplotlib) so the bytes depend only on the samples: fixed number formats,
no timestamps, no random ids. Equal axis scales, so turns look like turns; runs separated by a
``World.reset()`` are drawn as separate coloured lines.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from xml.sax.saxutils import escape

WIDTH, HEIGHT = 480, 400
LEFT, RIGHT, TOP, BOTTOM = 64, 16, 36, 52
COLOURS = ("#1f77b4", "#d62728", "#2ca02c", "#9467bd", "#ff7f0e", "#17becf")


def nice_step(span: float, target_ticks: int = 5) -> float:
    """A 1/2/5 x 10^k step giving about ``target_ticks`` ticks over ``span``."""
    raw = max(span, 1e-9) / target_ticks
    power = 10 ** math.floor(math.log10(raw))
    for m in (1, 2, 5, 10):
        if m * power >= raw:
            return m * power
    return 10 * power


def _ticks(lo: float, hi: float, step: float) -> list[float]:
    first = math.ceil(lo / step - 1e-9)
    last = math.floor(hi / step + 1e-9)
    return [k * step for k in range(first, last + 1)]


def _label(value: float, step: float) -> str:
    decimals = max(0, -math.floor(math.log10(step) + 1e-9))
    text = f"{value:.{decimals}f}"
    return "0" if text.strip("-0.") == "" else text


def path_svg(
    xs: Sequence[float], ys: Sequence[float], title: str, run_starts: Sequence[int] = ()
) -> str:
    """SVG text: the x-y path (metres) with axes, ticks, labels, start dot and end square."""
    if not xs:
        xs, ys = [0.0], [0.0]
    pw, ph = WIDTH - LEFT - RIGHT, HEIGHT - TOP - BOTTOM
    x0, x1, y0, y1 = min(xs), max(xs), min(ys), max(ys)
    span = max(x1 - x0, (y1 - y0) * pw / ph, 0.05) * 1.15  # at least 5 cm across, 15% margin
    cx, cy = (x0 + x1) / 2, (y0 + y1) / 2
    scale = pw / span
    xlo, xhi = cx - span / 2, cx + span / 2
    ylo, yhi = cy - ph / scale / 2, cy + ph / scale / 2

    def sx(x: float) -> float:
        return LEFT + (x - xlo) * scale

    def sy(y: float) -> float:
        return TOP + (yhi - y) * scale

    out = [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{WIDTH}" height="{HEIGHT}" '
        f'viewBox="0 0 {WIDTH} {HEIGHT}" font-family="sans-serif" font-size="11">',
        f'<rect x="0" y="0" width="{WIDTH}" height="{HEIGHT}" fill="#ffffff"/>',
        f'<text x="{WIDTH / 2:.1f}" y="20" text-anchor="middle" font-size="13">'
        f"{escape(title)}</text>",
    ]
    step = nice_step(span)
    for t in _ticks(xlo, xhi, step):
        out.append(
            f'<line x1="{sx(t):.1f}" y1="{TOP}" x2="{sx(t):.1f}" y2="{TOP + ph}" stroke="#e5e5e5"/>'
        )
        out.append(
            f'<text x="{sx(t):.1f}" y="{TOP + ph + 15}" text-anchor="middle">'
            f"{_label(t, step)}</text>"
        )
    for t in _ticks(ylo, yhi, step):
        out.append(
            f'<line x1="{LEFT}" y1="{sy(t):.1f}" x2="{LEFT + pw}" y2="{sy(t):.1f}" '
            'stroke="#e5e5e5"/>'
        )
        out.append(
            f'<text x="{LEFT - 6}" y="{sy(t) + 4:.1f}" text-anchor="end">{_label(t, step)}</text>'
        )
    out.append(
        f'<rect x="{LEFT}" y="{TOP}" width="{pw}" height="{ph}" fill="none" stroke="#333333"/>'
    )
    out.append(f'<text x="{LEFT + pw / 2:.1f}" y="{HEIGHT - 14}" text-anchor="middle">x (m)</text>')
    out.append(
        f'<text x="16" y="{TOP + ph / 2:.1f}" text-anchor="middle" '
        f'transform="rotate(-90 16 {TOP + ph / 2:.1f})">y (m)</text>'
    )

    bounds = [0, *[b for b in run_starts if 0 < b < len(xs)], len(xs)]
    runs = [(bounds[i], bounds[i + 1]) for i in range(len(bounds) - 1) if bounds[i] < bounds[i + 1]]
    for n, (a, b) in enumerate(runs):
        colour = COLOURS[n % len(COLOURS)]
        points = " ".join(f"{sx(x):.1f},{sy(y):.1f}" for x, y in zip(xs[a:b], ys[a:b], strict=True))
        out.append(
            f'<polyline points="{points}" fill="none" stroke="{colour}" stroke-width="1.6" '
            f'stroke-linejoin="round"/>'
        )
        out.append(f'<circle cx="{sx(xs[a]):.1f}" cy="{sy(ys[a]):.1f}" r="3.5" fill="{colour}"/>')
        out.append(
            f'<rect x="{sx(xs[b - 1]) - 3.5:.1f}" y="{sy(ys[b - 1]) - 3.5:.1f}" width="7" '
            f'height="7" fill="none" stroke="{colour}" stroke-width="1.6"/>'
        )
        if len(runs) > 1:
            ly = TOP + 14 + 14 * n
            out.append(
                f'<line x1="{LEFT + pw - 58}" y1="{ly - 4}" x2="{LEFT + pw - 44}" y2="{ly - 4}" '
                f'stroke="{colour}" stroke-width="2"/>'
            )
            out.append(f'<text x="{LEFT + pw - 40}" y="{ly}">run {n + 1}</text>')
    out.append(f'<text x="{LEFT}" y="{HEIGHT - 14}" fill="#666666">● start  □ end</text>')
    out.append("</svg>")
    return "\n".join(out) + "\n"
