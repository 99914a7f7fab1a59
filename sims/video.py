"""Video clips: WebM (VP8) with OpenCV, H.264 MP4 with an installed ffmpeg, a decode check.

Chromium plays WebM/VP8 and WebM/VP9 but not OpenCV's mp4 (``mp4v``), so clips are WebM. VP8 is
used because OpenCV's FFmpeg build encodes it about 8x faster than VP9 on this machine. FFmpeg
prints a harmless "tag VP80 is not supported" note when the writer opens (it substitutes
WebM's own tag); that C-level stderr line is silenced here, and a writer that did not open is
an error.

Safari on iPhones before iOS 17.4 and on older Macs plays no WebM, so a clip also gets an H.264
MP4 when an encoder is installed. OpenCV's own FFmpeg has none (pip's wheels leave x264 out:
measured, ``avc1``/``H264`` do not open), so :class:`Mp4Writer` pipes the frames to the
system's ``ffmpeg`` with libx264 (Debian's ``ffmpeg`` package has it). x264 output is
deterministic for a fixed thread count and settings, and ``-bitexact`` keeps the encoder's
version and time out of the MP4 header, so the same frames give the same bytes. Without such an
ffmpeg, clips are WebM only (docs/clips.md says which browsers that covers).
"""

from __future__ import annotations

import queue
import shutil
import subprocess
import threading
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import cv2
import numpy as np

from sims.quiet import quiet_fd

FOURCC = "VP80"


class VideoError(RuntimeError):
    pass


class WebmWriter:
    """Writes RGB uint8 frames of one fixed size to a .webm file.

    Encoding runs on a background thread (OpenCV releases the GIL while encoding), so a clip's
    next frame renders while the previous one is encoded; VP8 takes about a quarter of the
    per-frame time at 480x360. Errors from the thread surface on the next write or on close.
    """

    def __init__(self, path: Path, width: int, height: int, fps: float):
        self.path = Path(path)
        self.size = (width, height)
        self.frames = 0
        with quiet_fd(2):
            self._writer = cv2.VideoWriter(
                str(self.path), cv2.VideoWriter_fourcc(*FOURCC), float(fps), self.size
            )
        if not self._writer.isOpened():
            raise VideoError(f"OpenCV could not open a {FOURCC} WebM writer for {self.path}")
        self._queue: queue.Queue[np.ndarray | None] = queue.Queue(maxsize=4)
        self._error: BaseException | None = None
        self._thread = threading.Thread(target=self._encode, name="webm-encoder", daemon=True)
        self._thread.start()

    def _encode(self) -> None:
        while (frame := self._queue.get()) is not None:
            if self._error is None:
                try:
                    self._writer.write(cv2.cvtColor(frame, cv2.COLOR_RGB2BGR))
                except BaseException as exc:  # handed to the caller's thread
                    self._error = exc

    def write(self, rgb: np.ndarray) -> None:
        if self._error is not None:
            raise VideoError(f"encoding {self.path.name} failed: {self._error}")
        if rgb.shape[1::-1] != self.size:
            raise VideoError(
                f"frame is {rgb.shape[1]}x{rgb.shape[0]}, clip is {self.size[0]}x{self.size[1]}"
            )
        self._queue.put(rgb)
        self.frames += 1

    def close(self) -> None:
        if self._writer is not None:
            self._queue.put(None)
            self._thread.join()
            self._writer.release()
            self._writer = None
            if self._error is not None:
                raise VideoError(f"encoding {self.path.name} failed: {self._error}")
            fix_track_uid(self.path)

    def __enter__(self) -> WebmWriter:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


@lru_cache(maxsize=1)
def mp4_encoder() -> str | None:
    """``"ffmpeg <version> libx264"`` when the system ffmpeg encodes H.264, else None (part of
    a clip's cache key: installing an encoder renders the MP4s)."""
    exe = shutil.which("ffmpeg")
    if exe is None:
        return None
    try:
        encoders = subprocess.run(
            [exe, "-hide_banner", "-encoders"], capture_output=True, text=True, timeout=30
        ).stdout
        version = subprocess.run(
            [exe, "-version"], capture_output=True, text=True, timeout=30
        ).stdout.split("\n", 1)[0]
    except (OSError, subprocess.SubprocessError):
        return None
    if " libx264 " not in encoders:
        return None
    parts = version.split()
    return f"ffmpeg {parts[2] if len(parts) > 2 else '?'} libx264"


MP4_ARGS = (
    "-c:v", "libx264", "-preset", "medium", "-crf", "26", "-pix_fmt", "yuv420p",
    "-profile:v", "main", "-threads", "1", "-x264-params", "threads=1:lookahead-threads=1",
    "-movflags", "+faststart", "-map_metadata", "-1",
    "-fflags", "+bitexact", "-flags:v", "+bitexact",
)  # fmt: skip


class Mp4Writer:
    """Writes RGB uint8 frames to an H.264 MP4 through the system's ffmpeg (see the module
    docstring); same interface as :class:`WebmWriter`."""

    def __init__(self, path: Path, width: int, height: int, fps: float):
        exe = shutil.which("ffmpeg")
        if exe is None or mp4_encoder() is None:
            raise VideoError("no ffmpeg with libx264 is installed")
        self.path = Path(path)
        self.size = (width, height)
        self.frames = 0
        self._log = self.path.with_suffix(".ffmpeg.log")
        with open(self._log, "wb") as log:
            self._process = subprocess.Popen(
                [exe, "-hide_banner", "-nostdin", "-loglevel", "error", "-y",
                 "-f", "rawvideo", "-pix_fmt", "rgb24", "-s", f"{width}x{height}",
                 "-r", f"{fps:g}", "-i", "-", *MP4_ARGS, "-f", "mp4", str(self.path)],
                stdin=subprocess.PIPE, stdout=subprocess.DEVNULL, stderr=log,
            )  # fmt: skip

    def write(self, rgb: np.ndarray) -> None:
        if rgb.shape[1::-1] != self.size:
            raise VideoError(
                f"frame is {rgb.shape[1]}x{rgb.shape[0]}, clip is {self.size[0]}x{self.size[1]}"
            )
        assert self._process.stdin is not None
        try:
            self._process.stdin.write(np.ascontiguousarray(rgb, dtype=np.uint8).tobytes())
        except BrokenPipeError as exc:
            raise VideoError(f"encoding {self.path.name} failed: {self._error()}") from exc
        self.frames += 1

    def _error(self) -> str:
        try:
            text = self._log.read_text(encoding="utf-8", errors="replace").strip()
        except OSError:
            text = ""
        return text.splitlines()[-1] if text else f"ffmpeg exit code {self._process.returncode}"

    def close(self) -> None:
        if self._process.stdin is not None and not self._process.stdin.closed:
            try:
                self._process.stdin.close()
            except BrokenPipeError:
                pass
        code = self._process.wait()
        if code != 0:
            raise VideoError(f"encoding {self.path.name} failed: {self._error()}")
        self._log.unlink(missing_ok=True)

    def __enter__(self) -> Mp4Writer:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


# EBML ids (with their one-byte size 8) of the Matroska elements that carry the track's UID.
_UID_ELEMENTS = (b"\x73\xc5\x88", b"\x63\xc5\x88")  # TrackUID, TagTrackUID
_CLUSTER = b"\x1f\x43\xb6\x75"
FIXED_TRACK_UID = (1).to_bytes(8, "big")


def fix_track_uid(path: Path) -> None:
    """Replace the random track UID FFmpeg's Matroska muxer picks with 1, in place.

    The muxer draws the UID from a random seed unless it runs in bit-exact mode, which OpenCV's
    writer does not expose; it is the only thing that differs between two encodings of the same
    frames (measured), so the same clip becomes the same bytes. Only the header before the first
    Cluster is touched, and only at the TrackUID and TagTrackUID elements (same length).
    """
    with open(path, "r+b") as f:
        head = f.read(1 << 16)
        end = head.find(_CLUSTER)
        head = head[: end if end > 0 else len(head)]
        for marker in _UID_ELEMENTS:
            start = 0
            while (at := head.find(marker, start)) >= 0:
                f.seek(at + len(marker))
                f.write(FIXED_TRACK_UID)
                start = at + len(marker) + 8


@dataclass(frozen=True)
class VideoInfo:
    frames: int
    width: int
    height: int
    fps: float


def probe(path: Path, keep_frames: bool = False) -> tuple[VideoInfo, list[np.ndarray]]:
    """Decode the whole file (the real test that it plays); counts frames by reading them."""
    cap = cv2.VideoCapture(str(path))
    if not cap.isOpened():
        raise VideoError(f"cannot decode {path}")
    try:
        width = int(cap.get(cv2.CAP_PROP_FRAME_WIDTH))
        height = int(cap.get(cv2.CAP_PROP_FRAME_HEIGHT))
        fps = float(cap.get(cv2.CAP_PROP_FPS))
        frames, kept = 0, []
        while True:
            ok, frame = cap.read()
            if not ok:
                break
            frames += 1
            if keep_frames:
                kept.append(frame)
    finally:
        cap.release()
    return VideoInfo(frames, width, height, fps), kept


def write_png(path: Path, rgb: np.ndarray) -> None:
    if not cv2.imwrite(str(path), cv2.cvtColor(rgb, cv2.COLOR_RGB2BGR)):
        raise VideoError(f"could not write {path}")
