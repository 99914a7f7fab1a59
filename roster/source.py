"""Reading a roster file into lines: encodings, byte-order marks, line endings.

Rosters are typed by hand and exported from spreadsheets, so they arrive with a
UTF-8 BOM, CRLF endings, or (from Excel's "Unicode text") as UTF-16. All of that
is tolerated and reported as info; bytes that are not valid text are an error on
the line where they occur, and the rest of the file is still read so no other
line's students go unreported.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from .model import WHOLE_FILE, Diagnostic, RosterError

FORMATS = {".txt": "tsv", ".tsv": "tsv", ".csv": "csv", ".yml": "yaml", ".yaml": "yaml"}
SEPARATORS = {"tsv": "\t", "csv": ",", "yaml": None}


@dataclass
class SourceText:
    """A decoded file: its lines without line endings, plus what decoding noticed."""

    file: str
    lines: list[str]
    diagnostics: list[Diagnostic] = field(default_factory=list)

    @property
    def text(self) -> str:
        return "\n".join(self.lines)


def detect_format(path: Path) -> str:
    """Map a file extension to a roster format, or raise a RosterError saying what is accepted."""
    fmt = FORMATS.get(path.suffix.lower())
    if fmt is None:
        accepted = ", ".join(sorted(FORMATS))
        raise RosterError(
            str(path),
            WHOLE_FILE,
            "file",
            f"unsupported roster file type {path.suffix or '(none)'!r}; use one of {accepted}",
        )
    return fmt


def read_bytes(path: Path) -> bytes:
    """Read a file, turning OS failures into RosterError (the only exception load_roster raises)."""
    try:
        return path.read_bytes()
    except FileNotFoundError:
        raise RosterError(str(path), WHOLE_FILE, "file", "no such file") from None
    except IsADirectoryError:
        raise RosterError(
            str(path), WHOLE_FILE, "file", "is a directory, not a roster file"
        ) from None
    except OSError as exc:
        raise RosterError(
            str(path), WHOLE_FILE, "file", f"cannot read: {exc.strerror or exc}"
        ) from None


def _decode_utf8_reporting(data: bytes, file: str, sep: str | None) -> tuple[str, list[Diagnostic]]:
    """Decode UTF-8, replacing bad bytes with U+FFFD and reporting one error per affected line."""
    try:
        return data.decode("utf-8"), []
    except UnicodeDecodeError:
        pass
    diags: list[Diagnostic] = []
    pieces: list[str] = []
    pos = 0
    reported_lines: set[int] = set()
    while True:
        try:
            pieces.append(data[pos:].decode("utf-8"))
            break
        except UnicodeDecodeError as exc:
            bad = pos + exc.start
            pieces.append(data[pos:bad].decode("utf-8"))
            pieces.append("\ufffd")
            line_start = data.rfind(b"\n", 0, bad) + 1
            line = data.count(b"\n", 0, bad) + 1
            if line not in reported_lines:
                reported_lines.add(line)
                if sep is not None:
                    where = f"col {data.count(sep.encode(), line_start, bad) + 1}"
                else:
                    where = f"char {bad - line_start + 1}"
                diags.append(
                    Diagnostic(
                        file,
                        line,
                        where,
                        f"undecodable byte 0x{data[bad]:02x} "
                        "(file is not UTF-8; re-save it as UTF-8)",
                    )
                )
            pos = pos + exc.end
    return "".join(pieces), diags


def decode(data: bytes, file: str, fmt: str) -> SourceText:
    """Turn raw bytes into lines, reporting BOMs, UTF-16, CRLF and undecodable bytes."""
    diags: list[Diagnostic] = []
    sep = SEPARATORS.get(fmt)
    if data.startswith((b"\xff\xfe", b"\xfe\xff")):
        try:
            text = data.decode("utf-16")
        except UnicodeDecodeError as exc:
            diags.append(
                Diagnostic(file, 1, "file", f"invalid UTF-16 text at byte {exc.start}", "error")
            )
            text = data.decode("utf-16", errors="replace")
        diags.append(
            Diagnostic(file, 1, "file", "decoded as UTF-16 (byte-order mark found)", "info")
        )
        text = text.lstrip("\ufeff")
    else:
        if data.startswith(b"\xef\xbb\xbf"):
            data = data[3:]
            diags.append(Diagnostic(file, 1, "file", "UTF-8 byte-order mark removed", "info"))
        text, bad = _decode_utf8_reporting(data, file, sep)
        diags.extend(bad)
    if "\n" not in text and "\r" in text:
        diags.append(
            Diagnostic(file, 1, "file", "old Mac line endings (CR) treated as line breaks", "info")
        )
        text = text.replace("\r", "\n")
    lines = text.split("\n")
    if lines and lines[-1] == "":
        lines.pop()  # the final newline does not start another line
    crlf = 0
    for i, line in enumerate(lines):
        if line.endswith("\r"):
            lines[i] = line[:-1]
            crlf += 1
    if crlf:
        diags.append(
            Diagnostic(file, 1, "file", f"CRLF line endings normalised ({crlf} lines)", "info")
        )
    if fmt != "yaml":
        _fullwidth_to_ascii(lines, file, diags)
    return SourceText(file, lines, diags)


# Full-width letters and digits (typed with a Chinese input method: `４０９２３１０１`) -> ASCII.
_FULLWIDTH = {
    cp: cp - 0xFEE0
    for r in ((0xFF10, 0xFF19), (0xFF21, 0xFF3A), (0xFF41, 0xFF5A))
    for cp in range(r[0], r[1] + 1)
}


def _fullwidth_to_ascii(lines: list[str], file: str, diags: list[Diagnostic]) -> None:
    """Read full-width letters and digits as ASCII, so `４０９２３１０１` is the id 40923101 and
    `２ａｇ１` the label 2ag1; said once (count and first line). Other characters, full-width
    brackets of annotations included, are left as typed."""
    count = 0
    first = 0
    for i, line in enumerate(lines):
        if any(0xFF10 <= ord(ch) <= 0xFF5A for ch in line):
            new = line.translate(_FULLWIDTH)
            changed = sum(a != b for a, b in zip(line, new, strict=True))
            if changed:
                count += changed
                first = first or i + 1
                lines[i] = new
    if count:
        diags.append(
            Diagnostic(
                file,
                first,
                "file",
                f"{count} full-width letter(s) or digit(s) read as ASCII (first on this line)",
                "info",
            )
        )
