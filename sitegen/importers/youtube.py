"""YouTube iframes -> a click-to-load poster that loads nothing from YouTube until played.

cmsimde users embed many YouTube videos; each plain ``<iframe src="https://www.youtube.com/
embed/ID">`` makes every reader's browser contact YouTube (and Google's trackers) on page
view. The import replaces each with an iframe that has no ``src`` but a ``srcdoc``: a small
page of our own, inside the frame, with the video's title and a real ``<button>`` in a
``<form>`` whose action is the privacy-enhanced player (``www.youtube-nocookie.com/embed/
ID?autoplay=1``). Pressing it navigates the frame to the player. No JavaScript is involved
(nothing to fail, nothing to add to the theme), the button is a real, labelled, focusable
control, and until it is pressed the page requests nothing from any YouTube or Google host
(no thumbnail either). A link under the button opens the video on youtube.com instead.

``sitegen import cmsimde --youtube keep`` keeps the iframes as they were.
"""

from __future__ import annotations

import html
import re
from urllib.parse import parse_qs, urlencode, urlsplit

_HOSTS = {
    "youtube.com",
    "www.youtube.com",
    "m.youtube.com",
    "youtube-nocookie.com",
    "www.youtube-nocookie.com",
    "youtu.be",
}
_ID = re.compile(r"[A-Za-z0-9_-]{6,20}")
#: Player parameters worth keeping (where to start, which part, the player's look).
_KEEP = ("start", "end", "list", "index", "loop", "playlist", "controls", "rel", "cc_load_policy")
#: The title YouTube's "Share > Embed" code gives every video: no name at all.
_GENERIC_TITLES = {"youtube video player", "youtube video", "youtube"}
NOCOOKIE = "https://www.youtube-nocookie.com/embed/"

WORDS = {
    "en": {
        "play": "Play video",
        "label": "Play video: {title} (loads the YouTube player)",
        "note": "Nothing is loaded from YouTube until you press Play "
        "(privacy-enhanced mode, youtube-nocookie.com).",
        "watch": "Watch on YouTube",
        "video": "YouTube video",
    },
    "zh-TW": {
        "play": "播放影片",
        "label": "播放影片：{title}（載入 YouTube 播放器）",
        "note": "按下播放前不會從 YouTube 載入任何內容（隱私強化模式 youtube-nocookie.com）。",
        "watch": "在 YouTube 觀看",
        "video": "YouTube 影片",
    },
}

_STYLE = (
    "html,body{height:100%;margin:0}"
    "body{display:flex;flex-direction:column;align-items:center;justify-content:center;"
    "gap:.6em;padding:0 1em;box-sizing:border-box;background:#181818;color:#eee;"
    "font:15px/1.4 system-ui,sans-serif;text-align:center}"
    "form{margin:0}"
    "button{font:inherit;font-size:1.15em;padding:.55em 1.4em;border:2px solid #fff;"
    "border-radius:2em;background:#c4302b;color:#fff;cursor:pointer}"
    "button:hover{background:#e0403a}"
    "button:focus-visible{outline:3px solid #ffd54a;outline-offset:3px}"
    "p{margin:0;max-width:36em}.t{font-weight:600}.n{font-size:.85em;color:#ccc}"
    "a{color:#9cf}"
)


def video_id(src: str) -> tuple[str, dict[str, str]] | None:
    """(video id, player parameters kept) for a YouTube embed, watch or short URL; else None."""
    url = src.strip()
    if url.startswith("//"):
        url = "https:" + url
    try:
        parts = urlsplit(url)
    except ValueError:
        return None
    host = (parts.hostname or "").lower()
    if host not in _HOSTS:
        return None
    query = {k: v[0] for k, v in parse_qs(parts.query).items() if v}
    path = parts.path.rstrip("/")
    if host == "youtu.be":
        candidate = path.lstrip("/")
    elif path.startswith(("/embed/", "/v/", "/shorts/", "/live/")):
        candidate = path.split("/")[2] if path.count("/") >= 2 else ""
    elif path == "/watch":
        candidate = query.pop("v", "")
    else:
        return None
    if not _ID.fullmatch(candidate):
        return None
    kept = {k: query[k] for k in _KEEP if k in query}
    start = _seconds(query.get("t", ""))
    if start and "start" not in kept:  # a watch link's `t=1m30s` is the player's `start=90`
        kept["start"] = str(start)
    return candidate, kept


def _seconds(value: str) -> int:
    m = re.fullmatch(r"(?:(\d+)h)?(?:(\d+)m)?(?:(\d+)s?)?", value.strip())
    if not m or not value.strip():
        return 0
    h, mins, secs = (int(x) if x else 0 for x in m.groups())
    return h * 3600 + mins * 60 + secs


def poster(src: str, title: str, width: str, height: str, language: str) -> str | None:
    """The click-to-load iframe for a YouTube ``src`` (None when it is not a YouTube video)."""
    found = video_id(src)
    if found is None:
        return None
    vid, params = found
    words = WORDS.get(language, WORDS["en"])
    if title.strip().lower() in _GENERIC_TITLES:
        title = ""
    name = title.strip() or words["video"]
    hidden = "".join(
        f'<input type="hidden" name="{html.escape(k)}" value="{html.escape(v)}">'
        for k, v in [*params.items(), ("autoplay", "1")]
    )
    if vid == "videoseries":  # a playlist player: `embed/videoseries?list=...`
        watch = "https://www.youtube.com/playlist?" + urlencode({"list": params.get("list", "")})
    else:
        watch = "https://www.youtube.com/watch?" + urlencode({"v": vid, **params})
    doc = (
        f'<!doctype html><html lang="{language}"><meta charset="utf-8">'
        f"<title>{html.escape(name)}</title><style>{_STYLE}</style>"
        f'<p class="t">{html.escape(name)}</p>'
        f'<form action="{NOCOOKIE}{vid}" method="get">{hidden}'
        f'<button type="submit" aria-label="{html.escape(words["label"].format(title=name))}">'
        f"&#9654; {html.escape(words['play'])}</button></form>"
        f'<p class="n">{html.escape(words["note"])}</p>'
        f'<p class="n"><a href="{html.escape(watch)}" target="_blank" rel="noopener">'
        f"{html.escape(words['watch'])}</a></p></html>"
    )
    attrs = {
        "class": "youtube-poster",
        "title": f"{words['video']}: {name}" if title.strip() else words["video"],
        "width": width or "560",
        "height": height or "315",
        "allow": "autoplay; encrypted-media; picture-in-picture; fullscreen",
        "allowfullscreen": "",
        "data-youtube": vid,
        "srcdoc": doc,
    }
    # ' and " escaped too: the attribute holds a whole page; the build never reads inside it
    shown = " ".join(
        k if v == "" and k == "allowfullscreen" else f'{k}="{html.escape(v, quote=True)}"'
        for k, v in attrs.items()
    )
    return f"<iframe {shown}></iframe>"
