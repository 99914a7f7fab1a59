"""A clip's plots as small, dependency-free, deterministic SVG: the x-y path of the robot body
(``path.svg``) and its position and joints over time (``series.svg``, with a cursor the replay
viewer moves along the timeline).

Drawn by hand (no matplotlib) so the bytes depend only on the samples: fixed number formats,
no timestamps, no random ids. Equal axis scales on the path, so turns look like turns; runs
separated by a ``World.reset()`` are drawn as separate coloured lines.

Both are shown inline in the site's pages, so their colours come from CSS custom properties
(``--plot-bg``, ``--plot-fg``, ``--plot-grid``, ``--plot-c0``...) with light fallbacks: the
theme's dark mode restyles them, and the file opened on its own is the light plot. Sizes are
chosen for reading: a 400-unit-wide plot with 13-unit text keeps labels at least 11 px tall
down to a 340 px wide phone column.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from xml.sax.saxutils import escape

WIDTH, HEIGHT = 400, 340
LEFT, RIGHT, TOP, BOTTOM = 56, 12, 34, 46
FONT = 13
COLOURS = ("#1f6fb4", "#c62828", "#2e7d32", "#7b3fa8", "#d96800", "#00838f")
BG, FG, GRID, MUTED = "#ffffff", "#1f2328", "#e3e3e3", "#59636e"


def _paint(kind: str, var: str, fallback: str) -> str:
    return f'style="{kind}:var(--plot-{var},{fallback})"'


def colour(n: int) -> str:
    return _paint("stroke", f"c{n % len(COLOURS)}", COLOURS[n % len(COLOURS)])


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


def _open(width: int, height: int, title: str, extra: str = "") -> list[str]:
    return [
        f'<svg xmlns="http://www.w3.org/2000/svg" width="{width}" height="{height}" '
        f'viewBox="0 0 {width} {height}" font-family="sans-serif" font-size="{FONT}" '
        f'class="plot-svg"{extra} role="img" aria-label="{escape(title, {chr(34): "&quot;"})}">',
        f'<rect x="0" y="0" width="{width}" height="{height}" {_paint("fill", "bg", BG)}/>',
        f'<text x="{width / 2:.1f}" y="20" text-anchor="middle" font-size="{FONT + 1}" '
        f"{_paint('fill', 'fg', FG)}>{escape(title)}</text>",
    ]


def _text(x: float, y: float, text: str, anchor: str = "middle", extra: str = "") -> str:
    return (
        f'<text x="{x:.1f}" y="{y:.1f}" text-anchor="{anchor}" {_paint("fill", "fg", FG)}'
        f"{extra}>{escape(text)}</text>"
    )


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

    out = _open(WIDTH, HEIGHT, title)
    grid = _paint("stroke", "grid", GRID)
    step = nice_step(span)
    for t in _ticks(xlo, xhi, step):
        out.append(f'<line x1="{sx(t):.1f}" y1="{TOP}" x2="{sx(t):.1f}" y2="{TOP + ph}" {grid}/>')
        out.append(_text(sx(t), TOP + ph + 16, _label(t, step)))
    for t in _ticks(ylo, yhi, step):
        out.append(f'<line x1="{LEFT}" y1="{sy(t):.1f}" x2="{LEFT + pw}" y2="{sy(t):.1f}" {grid}/>')
        out.append(_text(LEFT - 6, sy(t) + 4, _label(t, step), "end"))
    out.append(
        f'<rect x="{LEFT}" y="{TOP}" width="{pw}" height="{ph}" fill="none" '
        f"{_paint('stroke', 'fg', FG)}/>"
    )
    out.append(_text(LEFT + pw / 2, HEIGHT - 10, "x (m)"))
    mid = TOP + ph / 2
    out.append(_text(14, mid, "y (m)", extra=f' transform="rotate(-90 14 {mid:.1f})"'))

    bounds = [0, *[b for b in run_starts if 0 < b < len(xs)], len(xs)]
    runs = [(bounds[i], bounds[i + 1]) for i in range(len(bounds) - 1) if bounds[i] < bounds[i + 1]]
    for n, (a, b) in enumerate(runs):
        c = COLOURS[n % len(COLOURS)]
        stroke = colour(n)
        fill = _paint("fill", f"c{n % len(COLOURS)}", c)
        points = " ".join(f"{sx(x):.1f},{sy(y):.1f}" for x, y in zip(xs[a:b], ys[a:b], strict=True))
        out.append(
            f'<polyline points="{points}" fill="none" {stroke} stroke-width="1.8" '
            f'stroke-linejoin="round"/>'
        )
        out.append(f'<circle cx="{sx(xs[a]):.1f}" cy="{sy(ys[a]):.1f}" r="4" {fill}/>')
        out.append(
            f'<rect x="{sx(xs[b - 1]) - 4:.1f}" y="{sy(ys[b - 1]) - 4:.1f}" width="8" '
            f'height="8" fill="none" {stroke} stroke-width="1.8"/>'
        )
        if len(runs) > 1:
            ly = TOP + 16 + 16 * n
            out.append(
                f'<line x1="{LEFT + pw - 66}" y1="{ly - 4}" x2="{LEFT + pw - 50}" y2="{ly - 4}" '
                f'{stroke} stroke-width="2"/>'
            )
            out.append(_text(LEFT + pw - 46, ly, f"#{n + 1}", "start"))
    out.append(_text(LEFT, HEIGHT - 10, "● → □", "start"))
    out.append("</svg>")
    return "\n".join(out) + "\n"


SERIES_PANEL = 120  # height of one panel of series.svg
MAX_POINTS = 500  # per line: a longer run is thinned to every k-th sample


def _panel(
    out: list[str],
    top: float,
    times: list[float],
    lines: list[tuple[str, list[float | None]]],
    unit: str,
    t_end: float,
    first_colour: int,
) -> None:
    pw = WIDTH - LEFT - RIGHT
    ph = SERIES_PANEL
    values = [v for _, vs in lines for v in vs if v is not None]
    lo, hi = (min(values), max(values)) if values else (0.0, 1.0)
    if hi - lo < 1e-9:
        lo, hi = lo - 0.5, hi + 0.5
    pad = (hi - lo) * 0.08
    lo, hi = lo - pad, hi + pad
    step = nice_step(hi - lo, 4)

    def sx(t: float) -> float:
        return LEFT + t / max(t_end, 1e-9) * pw

    def sy(v: float) -> float:
        return top + (hi - v) / (hi - lo) * ph

    grid = _paint("stroke", "grid", GRID)
    for v in _ticks(lo, hi, step):
        out.append(f'<line x1="{LEFT}" y1="{sy(v):.1f}" x2="{LEFT + pw}" y2="{sy(v):.1f}" {grid}/>')
        out.append(_text(LEFT - 6, sy(v) + 4, _label(v, step), "end"))
    out.append(
        f'<rect x="{LEFT}" y="{top}" width="{pw}" height="{ph}" fill="none" '
        f"{_paint('stroke', 'fg', FG)}/>"
    )
    mid = top + ph / 2
    out.append(_text(14, mid, unit, extra=f' transform="rotate(-90 14 {mid:.1f})"'))
    every = max(1, math.ceil(len(times) / MAX_POINTS))
    places = legend_places([name for name, _ in lines])
    for n, (name, vs) in enumerate(lines):
        pts = [
            f"{sx(t):.1f},{sy(v):.1f}"
            for t, v in list(zip(times, vs, strict=True))[::every]
            if v is not None
        ]
        if len(pts) >= 2:
            out.append(
                f'<polyline points="{" ".join(pts)}" fill="none" {colour(first_colour + n)} '
                'stroke-width="1.6" stroke-linejoin="round"/>'
            )
        x, row = places[n]
        y = top - 6 - LEGEND_ROW * (max(r for _, r in places) - row)
        out.append(
            f'<line x1="{x}" y1="{y - 4}" x2="{x + 14}" y2="{y - 4}" '
            f'{colour(first_colour + n)} stroke-width="3"/>'
        )
        out.append(_text(x + 18, y, name, "start"))


LEGEND_ROW = 16
CHAR = 7.5  # a generous average width of a 13-unit sans-serif character


def legend_places(names: list[str]) -> list[tuple[float, int]]:
    """(x, row) of each legend entry: rows above a panel, wrapped to the plot's width."""
    out, x, row = [], float(LEFT), 0
    for name in names:
        width = 22 + CHAR * len(name)
        if x > LEFT and x + width > WIDTH - RIGHT:
            x, row = float(LEFT), row + 1
        out.append((x, row))
        x += width + 10
    return out


def series_svg(recording, fps: float) -> str:
    """Position (x, y in m) and joints (degrees or rad/s) over simulated time: one panel each,
    sharing the time axis, with a cursor line (``class="plot-cursor"``) at t = 0. The root
    carries ``data-t-end`` and the plot area's x range (``data-x0``/``data-x1``, viewBox
    units) so the replay viewer can put the cursor at any time."""
    columns = recording.columns
    times = [float(t or 0.0) for t in recording.column("t")]
    t_end = max(len(times) / fps, 1e-3)
    joints = [c for c in columns[8:] if c.endswith(("_deg", "_rad_s"))]  # after the pose columns
    panels = [("m", [("x", recording.column("x")), ("y", recording.column("y"))])]
    if joints:
        unit = "deg" if joints[0].endswith("_deg") else "rad/s"
        names = [(c.removesuffix("_rad_s").removesuffix("_deg"), c) for c in joints]
        panels.append((unit, [(label, recording.column(c)) for label, c in names]))
    tops, y = [], 22.0  # each panel below its legend rows
    for _, lines in panels:
        rows = 1 + max(r for _, r in legend_places([name for name, _ in lines]))
        y += LEGEND_ROW * rows + 6
        tops.append(y)
        y += SERIES_PANEL
    bottom = y
    height = int(bottom + BOTTOM)
    pw = WIDTH - LEFT - RIGHT
    title = recording.subject
    extra = f' data-t-end="{t_end:g}" data-x0="{LEFT}" data-x1="{LEFT + pw}"'
    out = _open(WIDTH, height, title, extra)
    colours = 0
    for top, (unit, lines) in zip(tops, panels, strict=True):
        _panel(out, top, times, lines, unit, t_end, colours)
        colours += len(lines)
    step = nice_step(t_end, 5)
    for t in _ticks(0.0, t_end, step):
        x = LEFT + t / t_end * pw
        out.append(_text(x, bottom + 16, _label(t, step)))
    out.append(_text(LEFT + pw / 2, height - 10, "t (s)"))
    out.append(
        f'<line class="plot-cursor" x1="{LEFT}" y1="{tops[0]}" x2="{LEFT}" y2="{bottom}" '
        f'{_paint("stroke", "cursor", "#d96800")} stroke-width="2"/>'
    )
    out.append("</svg>")
    return "\n".join(out) + "\n"
