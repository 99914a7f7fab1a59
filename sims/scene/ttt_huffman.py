"""Huffman decompression of a ``.ttt`` body, table-driven and vectorised with numpy.

What the file holds (from CoppeliaSim's serializer, which uses Marcus Geelnard's public-domain
"Basic Compression Library" Huffman coder): bits are read most significant first; the tree comes
first, depth first, each node one bit (1 = leaf followed by its 8-bit symbol, 0 = inner node
followed by its two children, the "0" branch first); the coded symbols follow directly, with no
end marker (the uncompressed size is in the file header). A tree made of a single leaf means every
symbol is that leaf and takes no bits.

Why vectorised: decoding bit by bit in Python costs about 1 µs per output byte, several seconds for
a 2 MB scene. Here every bit position gets its next ``L`` bits as an integer (``L`` = longest code),
one table look-up gives the code length and symbol that *would* start there, and the chain of real
code starts is followed in blocks: all blocks step at once (numpy), then a short pass joins them
using Huffman codes' self-synchronisation (a decode started at a wrong bit falls onto the true code
boundaries after a few symbols). Codes longer than 24 bits (possible only for extremely skewed
data) take a plain, slow decoder that gives the same result.

Bounded memory: the arrays above take about 90 bytes per compressed byte, so the stream is
decoded in windows of ``WINDOW_BITS`` (a quarter of a megabyte of compressed data, ~25 MB of
work arrays whatever the file's size); the output grows window by window and is never allocated
at the size the header claims (the caller bounds that claim first, sims/scene/ttt.py).
"""

from __future__ import annotations

import numpy as np

MAX_TABLE_BITS = 24
BLOCK_SYMBOLS = 512
GROUP_BITS = 256
WINDOW_BITS = 1 << 21  # compressed bits decoded at once (256 KiB)


class HuffmanError(ValueError):
    """The compressed stream is not a valid Huffman stream (corrupt or truncated)."""


def _read_tree(data: bytes) -> tuple[dict[int, tuple[int, int]], int]:
    """Read the tree at the start of ``data``; return {symbol: (code, length)} and the bit
    position where the coded symbols start."""
    nbits = len(data) * 8
    pos = 0
    codes: dict[int, tuple[int, int]] = {}
    stack: list[tuple[int, int]] = [(0, 0)]  # (code, depth) of nodes still to read
    nodes = 0
    while stack:
        code, depth = stack.pop()
        nodes += 1
        if nodes > 511 or pos + 1 > nbits or depth > 32:
            raise HuffmanError("the Huffman tree is corrupt or truncated")
        leaf = (data[pos >> 3] >> (7 - (pos & 7))) & 1
        pos += 1
        if leaf:
            if pos + 8 > nbits:
                raise HuffmanError("the Huffman tree is truncated")
            sym = 0
            for _ in range(8):
                sym = (sym << 1) | ((data[pos >> 3] >> (7 - (pos & 7))) & 1)
                pos += 1
            if sym in codes:
                raise HuffmanError("the Huffman tree names a symbol twice")
            codes[sym] = (code, depth)
        else:  # children: "0" branch first, so push it last
            stack.append(((code << 1) | 1, depth + 1))
            stack.append((code << 1, depth + 1))
    return codes, pos


def decompress(data: bytes, size: int) -> bytes:
    """Decode ``size`` bytes from the Huffman stream ``data``. Raises :class:`HuffmanError` when
    the stream ends before ``size`` symbols are decoded or the tree is corrupt."""
    if size <= 0:
        return b""
    codes, start = _read_tree(data)
    if len(codes) == 1:
        ((sym, (_code, depth)),) = codes.items()
        if depth == 0:
            return bytes([sym]) * size
    longest = max(length for _code, length in codes.values())
    if longest > MAX_TABLE_BITS:
        return _decompress_slow(data, size, codes, start)
    return _decompress_table(data, size, codes, start, longest)


def _tables(codes: dict[int, tuple[int, int]], width: int) -> tuple[np.ndarray, np.ndarray]:
    lengths = np.zeros(1 << width, dtype=np.uint8)  # 0 = no code starts with these bits
    symbols = np.zeros(1 << width, dtype=np.uint8)
    for sym, (code, length) in codes.items():
        lo = code << (width - length)
        hi = (code + 1) << (width - length)
        lengths[lo:hi] = length
        symbols[lo:hi] = sym
    return lengths, symbols


def _words(data: bytes, start: int) -> np.ndarray:
    """The 32 bits starting at every byte from bit ``start`` on (bits past the end read 0)."""
    raw = np.frombuffer(data, dtype=np.uint8)[start >> 3 :]
    n = len(raw)
    padded = np.zeros(n + 4, dtype=np.uint32)
    padded[:n] = raw
    return (
        (padded[:n] << 24)
        | (padded[1 : n + 1] << 16)
        | (padded[2 : n + 2] << 8)
        | padded[3 : n + 3]
    )


def _window(words: np.ndarray, bits: np.ndarray, width: int) -> np.ndarray:
    """The ``width`` bits at the given bit positions (counted from the first byte of ``words``;
    ``width`` is at most 25: a 32-bit word read at any bit offset)."""
    shift = (32 - width - (bits & 7)).astype(np.uint32)
    return (words[bits >> 3] >> shift) & np.uint32((1 << width) - 1)


def _decompress_table(
    data: bytes, size: int, codes: dict[int, tuple[int, int]], start: int, width: int
) -> bytes:
    """Decode window by window: each window takes every code whose bits all lie in it."""
    len_table, sym_table = _tables(codes, width)
    parts: list[bytes] = []
    done, pos = 0, start
    while done < size:
        out, end = _window_decode(data, pos, size - done, len_table, sym_table, width)
        if not out:
            raise HuffmanError(f"the compressed data ends after {done} of {size} bytes")
        parts.append(out)
        done += len(out)
        pos = end
    return b"".join(parts)


def _window_decode(
    data: bytes, pos: int, want: int, len_table: np.ndarray, sym_table: np.ndarray, width: int
) -> tuple[bytes, int]:
    """Up to ``want`` symbols from bit ``pos`` on, from at most ``WINDOW_BITS`` of ``data``:
    the codes whose bits all lie in the window (a code running past it would be read with 0
    bits; by the prefix property such a code never looks shorter than what is left, so it is
    never taken). Returns them and the bit position after the last one."""
    lo = pos >> 3
    piece = data[lo : lo + (WINDOW_BITS >> 3)]
    skip = pos & 7  # the first code starts this many bits into the first byte
    words = _words(piece, 0)
    nbits = len(piece) * 8 - skip
    if nbits <= 0:  # the data ended
        return b"", pos
    # Code length starting at each bit; past the end nothing decodes (0 parks a decode there).
    by_offset = np.empty((len(words), 8), dtype=np.uint8)
    mask = np.uint32((1 << width) - 1)
    for b in range(8):
        by_offset[:, b] = len_table[(words >> np.uint32(32 - b - width)) & mask]
    step = np.zeros(nbits + 1, dtype=np.uint8)
    step[:nbits] = by_offset.reshape(-1)[skip : skip + nbits]
    del by_offset
    starts = _block_starts(step, nbits)
    ends = np.append(starts[1:], nbits)
    paths, first, exits = _block_paths(step, starts, ends)
    positions = _join_fast(paths, first, exits, step, ends, nbits, want)
    if positions is None:  # a block never fell in step: follow the chain block by block
        positions = _join(paths, first, exits, step, ends, nbits, want)
    lengths = step[positions]
    fits = (lengths > 0) & (positions + lengths <= nbits)
    if not fits.all():
        positions = positions[: int(np.argmin(fits))]
    if not len(positions):
        return b"", pos
    last = int(positions[-1])
    symbols = sym_table[_window(words, positions + skip, width)].tobytes()
    return symbols, pos + last + int(step[last])


def _block_starts(step: np.ndarray, nbits: int) -> np.ndarray:
    """Block boundaries holding about ``BLOCK_SYMBOLS`` codes each (estimated from the code
    lengths, counted per group of ``GROUP_BITS`` bits), so that all blocks finish their decode in
    about the same number of rounds."""
    groups = -(-nbits // GROUP_BITS)
    weight = np.zeros(groups * GROUP_BITS, dtype=np.uint8)
    weight[:nbits] = 64 // np.maximum(step[:nbits], 1)  # 64 / code length: a code's share
    per_group = weight.reshape(groups, GROUP_BITS).sum(axis=1, dtype=np.int64)
    expected = np.cumsum(per_group) / 64.0
    cut = np.searchsorted(expected, np.arange(BLOCK_SYMBOLS, expected[-1], BLOCK_SYMBOLS))
    starts = np.unique(np.concatenate([[0], (cut + 1) * GROUP_BITS]).astype(np.int64))
    return starts[starts < max(nbits, 1)]


def _block_paths(
    step: np.ndarray, starts: np.ndarray, ends: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Decode every block from its first bit, all blocks at once, each until it passes its end.
    Returns the visited positions block after block (``paths[first[b]:first[b + 1]]`` for block
    ``b``) and, per block, the first position past its end (the end of the data when a decode
    stops on a position where no code fits)."""
    nblocks = len(starts)
    nbits = len(step) - 1
    ids = np.arange(nblocks, dtype=np.int64)
    pos = starts.copy()
    rounds: list[tuple[np.ndarray, np.ndarray]] = []
    exits = np.full(nblocks, nbits, dtype=np.int64)
    while len(ids):
        rounds.append((ids, pos))
        jump = step[pos]
        nxt = pos + jump
        going = (nxt < ends[ids]) & (jump > 0)
        done = ~going
        exits[ids[done]] = np.where(jump[done] > 0, np.minimum(nxt[done], nbits), nbits)
        ids, pos = ids[going], nxt[going]
    counts = np.bincount(np.concatenate([r[0] for r in rounds]), minlength=nblocks)
    first = np.zeros(nblocks + 1, dtype=np.int64)
    np.cumsum(counts, out=first[1:])
    paths = np.empty(int(first[-1]), dtype=np.int64)
    for k, (rid, rpos) in enumerate(rounds):
        paths[first[rid] + k] = rpos
    return paths, first, exits


def _join_fast(
    paths: np.ndarray,
    first: np.ndarray,
    exits: np.ndarray,
    step: np.ndarray,
    ends: np.ndarray,
    nbits: int,
    size: int,
) -> np.ndarray | None:
    """The real chain of code starts, all blocks at once: each block is entered where the
    previous block's decode left it; from there the real codes are followed until they meet the
    block's own decode, whose rest is then the chain. A block whose decode is never met (a run of
    equal-length codes read out of step) is crossed code by code, and the blocks after it are
    re-entered where the real chain leaves it. None when that takes too long."""
    nblocks = len(ends)
    block_of = np.repeat(np.arange(nblocks, dtype=np.int32), np.diff(first))
    # a block's decode stays inside the block: "visited and inside block b" = on b's decode
    owned = np.zeros(nbits + 1, dtype=bool)
    owned[paths] = True
    entries = np.concatenate([[0], exits[:-1]])
    ids = np.arange(nblocks, dtype=np.int32)
    pos = entries.copy()
    met = np.full(nblocks, nbits + 1, dtype=np.int64)  # nothing of a crossed block's decode
    crossed = np.zeros(nblocks, dtype=bool)
    extra_pos: list[np.ndarray] = []
    extra_ids: list[np.ndarray] = []
    for _round in range(4096):
        hit = owned[pos] & (pos < ends[ids])
        met[ids[hit]] = pos[hit]
        ids, pos = ids[~hit], pos[~hit]
        out = (pos >= ends[ids]) | (step[pos] == 0)
        crossed[ids[out]] = True
        ids, pos = ids[~out], pos[~out]
        if not len(ids):
            break
        extra_pos.append(pos)
        extra_ids.append(ids)
        pos = np.minimum(pos + step[pos], nbits)
    else:
        return None
    ex_pos = np.concatenate(extra_pos) if extra_pos else np.zeros(0, dtype=np.int64)
    ex_ids = np.concatenate(extra_ids) if extra_ids else np.zeros(0, dtype=np.int32)
    # A crossed block leaves the real chain somewhere its neighbour's first pass did not
    # assume: redo the blocks from there, one by one, until the chain is back in step.
    redone = np.zeros(nblocks, dtype=bool)
    fixed: list[int] = []
    settled = 0  # blocks before this one are final
    for c in np.flatnonzero(crossed).tolist():
        if c < settled:
            continue
        b, entry = c, int(entries[c])
        while True:
            redone[b] = True
            end = int(ends[b])
            while entry < end and not owned[entry]:
                if step[entry] == 0:
                    raise HuffmanError("the compressed data is corrupt (no code fits)")
                fixed.append(entry)
                entry = min(entry + int(step[entry]), nbits)
            if len(fixed) > 1 << 22:
                return None
            if entry < end:  # met the block's own decode: the rest of the block is the chain
                met[b] = entry
                entry = int(exits[b])
            else:
                met[b] = nbits + 1
            b += 1
            if b >= nblocks or entry == entries[b]:
                break
        settled = b
    keep = ~redone[ex_ids] if len(ex_ids) else np.zeros(0, dtype=bool)
    more = np.sort(np.concatenate([ex_pos[keep], np.array(fixed, dtype=np.int64)]))
    chain = paths[paths >= met[block_of]]
    if len(more):
        chain = np.insert(chain, np.searchsorted(chain, more), more)
    return chain[:size]  # fewer than ``size`` when the data ends first (the caller checks)


def _join(
    paths: np.ndarray,
    first: np.ndarray,
    exits: np.ndarray,
    step: np.ndarray,
    ends: np.ndarray,
    nbits: int,
    size: int,
) -> np.ndarray:
    """Follow the real chain of code starts from bit 0 through the blocks, one block at a time:
    once it meets a block's own decode, the rest of that block is the block's decode; a block
    whose decode it never meets (a run of equal-length codes read out of step) is crossed code by
    code."""
    nblocks = len(ends)
    owned = np.zeros(nbits + 1, dtype=bool)  # on some block's decode (which stays in its block)
    owned[paths] = True
    parts: list[np.ndarray] = []
    count = 0
    entry = 0
    for b in range(nblocks):
        if count >= size:
            break
        end = int(ends[b])
        if entry >= end:
            continue
        extra: list[int] = []
        while entry < end and not owned[entry]:
            jump = int(step[entry])
            if jump == 0:  # no code fits here: the chain ends (the caller checks its length)
                entry = nbits
                break
            extra.append(entry)
            entry = min(entry + jump, nbits)
        if extra:
            parts.append(np.array(extra, dtype=np.int64))
            count += len(extra)
        if entry >= end:  # crossed the whole block without meeting its decode
            continue
        stop = int(first[b + 1])
        i = int(first[b]) + int(np.searchsorted(paths[first[b] : stop], entry))
        parts.append(paths[i:stop])
        count += stop - i
        entry = int(exits[b])
    return np.concatenate(parts)[:size] if parts else np.zeros(0, dtype=np.int64)


def _decompress_slow(
    data: bytes, size: int, codes: dict[int, tuple[int, int]], start: int
) -> bytes:
    lookup = {(length, code): sym for sym, (code, length) in codes.items()}
    if (0, 0) in lookup:  # a one-leaf tree: every symbol is that leaf, no bits
        return bytes([lookup[(0, 0)]]) * size
    out = bytearray()
    pos = start
    nbits = len(data) * 8
    while len(out) < size:
        code = 0
        length = 0
        while True:
            if pos >= nbits or length > 32:
                raise HuffmanError(f"the compressed data ends after {len(out)} of {size} bytes")
            code = (code << 1) | ((data[pos >> 3] >> (7 - (pos & 7))) & 1)
            pos += 1
            length += 1
            sym = lookup.get((length, code))
            if sym is not None:
                out.append(sym)
                break
    return bytes(out)
