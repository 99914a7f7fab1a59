"""Issue 33, scene files: a hostile scene file ends in one clear line, within bounded memory and
linear time (docs/security.md, "Scene files"; the bounds are sims/scene/limits.py).

Memory is measured with tracemalloc (numpy's arrays included) for the readers, and as the
peak resident size of a fresh process for the command line."""

from __future__ import annotations

import os
import struct
import subprocess
import sys
import textwrap
import time
import tracemalloc
from pathlib import Path

import pytest
from scene_read_helpers import chunk, floats, ints, scene_object, ttt_file
from shared_data import shared
from sitegen_helpers import REPO

from sims.scene import limits, ttt
from sims.scene.errors import SceneError
from sims.scene.load import load_scene
from sims.scene.model import Scene, SceneObject
from sims.scene.resolve import SceneFileError, open_scene
from sims.scene.show import json_report, text_report

MB = 1024 * 1024


def _header(size: int, compression: int = 1) -> bytes:
    head = b"VREP" + struct.pack("<ii", 22, 18) + bytes([compression]) + struct.pack("<i", size)
    head += struct.pack("<i", 0) + struct.pack("<H", 40100) + struct.pack("<I", 0x1001)
    return head + b"\x01\x01" + b"\x00" * 992


def _zero_bomb(claim: int) -> bytes:
    """A Huffman tree of one leaf (the byte 0) takes no bits per symbol: 1 KB claims anything."""
    return _header(claim) + bytes([0b10000000, 0]) + b"\x00" * 1000


def _peak(fn) -> tuple[object, float]:
    """``fn()`` (or the exception it raised) and the peak of traced memory meanwhile, in MB."""
    tracemalloc.start()
    try:
        try:
            value: object = fn()
        except SceneError as exc:
            value = exc
        return value, tracemalloc.get_traced_memory()[1] / MB
    finally:
        tracemalloc.stop()


def _cli_peak(*args: str, timeout: float = 120) -> tuple[subprocess.CompletedProcess, float]:
    """``sitegen scene ARGS`` in a fresh process; its peak resident size in MB."""
    code = textwrap.dedent(
        f"""
        import resource, sys
        from sims.scene.show import main
        try:
            code = main({list(args)!r})
        finally:
            sys.stdout.flush()
            # VmHWM: this process image's own peak (ru_maxrss carries the parent's peak
            # across fork and exec, so a large pytest process would be counted)
            status = open("/proc/self/status").read().split("VmHWM:")[1]
            peak = int(status.split()[0]) if status else resource.getrusage(
                resource.RUSAGE_SELF).ru_maxrss
            print(f"PEAK {{peak}}", file=sys.stderr)
        raise SystemExit(code)
        """
    )
    proc = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO, timeout=timeout
    )
    peak = next(x for x in proc.stderr.splitlines() if x.startswith("PEAK "))
    return proc, int(peak.split()[1]) / 1024


def _errors(proc: subprocess.CompletedProcess) -> list[str]:
    return [x for x in proc.stderr.splitlines() if not x.startswith("PEAK ")]


# --- decompression -------------------------------------------------------------------------


def test_a_ttt_claiming_far_more_than_its_body_is_refused_before_anything_is_decoded(tmp_path):
    bomb = tmp_path / "bomb.ttt"
    bomb.write_bytes(_zero_bomb(128 * MB))
    err, peak = _peak(lambda: load_scene(bomb))
    assert isinstance(err, SceneError) and err.obj == "header"
    assert "claims 134217728 bytes of scene data from 1002 compressed bytes" in err.message
    assert "made to exhaust memory" in err.message
    assert peak < 5, peak  # it was 4.2 GB
    bomb.write_bytes(_zero_bomb(1 << 30))  # the largest claim the reader used to accept
    proc, rss = _cli_peak("show", str(bomb))
    assert proc.returncode == 1 and proc.stdout == ""
    (line,) = _errors(proc)
    assert line.startswith(f"{bomb}: error: header: claims {1 << 30} bytes") and rss < 512


def test_a_truthful_stream_that_shrinks_more_than_real_scenes_do_is_refused(tmp_path):
    """Two symbols, one bit each: a real Huffman stream 8 times smaller than its data."""
    data = (b"\x00" * 4095 + b"\x01") * 64
    path = tmp_path / "dense.ttt"
    path.write_bytes(ttt_file(data[:-3], compress=True))
    with pytest.raises(SceneError) as err:
        load_scene(path)
    assert err.value.obj == "header" and "times as many" in err.value.message
    assert f"compress less than {limits.MAX_RATIO} times" in err.value.message


@pytest.mark.needs_shared("data", "scenes")
def test_every_course_scene_stays_well_inside_the_ratio_bound():
    ratios = {}
    for path in sorted(shared("data", "scenes").rglob("*.ttt")):
        data = path.read_bytes()
        _version, _compression, size, _program = ttt.read_header(data, str(path))
        ratios[path.name] = size / (len(data) - ttt.HEADER_SIZE)
    assert len(ratios) >= 19 and max(ratios.values()) < 1.6 < limits.MAX_RATIO / 2, ratios


def test_decoding_works_in_windows_of_bounded_memory(monkeypatch):
    """The windowed decoder gives the bytes the encoder was given, window size regardless,
    and its work arrays follow the window, not the file (a whole-file decode took about 90
    bytes per compressed byte)."""
    from scene_read_helpers import huffman_compress

    from sims.scene import ttt_huffman

    rng = __import__("random").Random(7)
    data = bytes(rng.choice(b"aaaaaabbbcdefgh\x00\x01\xff") for _ in range(1 << 16))
    packed = huffman_compress(data)
    for window in (1 << 10, 1 << 13, 1 << 21):
        monkeypatch.setattr(ttt_huffman, "WINDOW_BITS", window)
        assert ttt_huffman.decompress(packed, len(data)) == data
    monkeypatch.setattr(ttt_huffman, "WINDOW_BITS", 1 << 13)
    _, peak = _peak(lambda: ttt_huffman.decompress(packed, len(data)))
    assert peak * MB < 20 * len(packed), (peak, len(packed))
    with pytest.raises(ttt_huffman.HuffmanError, match="ends after"):
        ttt_huffman.decompress(packed[: len(packed) // 2], len(data))


def test_millions_of_empty_chunks_cost_one_note(tmp_path):
    body = b"\x00" * (7 * 60000)  # 60,000 chunks named "\0\0\0" of no bytes
    path = tmp_path / "zeros.ttt"
    path.write_bytes(_header(len(body) + 3, compression=0) + body + b"EOF")
    scene, peak = _peak(lambda: load_scene(path))
    assert isinstance(scene, Scene) and not scene.objects
    assert [n.message for n in scene.notes] == [
        "unknown top-level chunk '\\x00\\x00\\x00' skipped (60000 times)"
    ]
    assert peak < 3, peak  # the body itself (0.4 MB, read and held) and little else


# --- what is read ----------------------------------------------------------------------------


def test_devices_pipes_and_oversized_files_are_refused_unread(tmp_path):
    fifo = tmp_path / "pipe.ttt"
    os.mkfifo(fifo)
    big = tmp_path / "big.ttt"
    with open(big, "wb") as fh:  # sparse: nothing is written, the size is what counts
        fh.truncate(limits.MAX_FILE_BYTES + 1)
    started = time.monotonic()
    for path, expected in (
        (Path("/dev/zero"), "not a regular file (a device or a pipe): not read"),
        (fifo, "not a regular file (a device or a pipe): not read"),
        (big, f"{limits.MAX_FILE_BYTES + 1} bytes: larger than {limits.MAX_FILE_BYTES} bytes"),
    ):
        with pytest.raises(SceneError) as err:
            load_scene(path)
        assert err.value.obj == "file" and err.value.message.startswith(expected)
        with pytest.raises(SceneFileError) as err2:
            open_scene(str(path)) if path != Path("/dev/zero") else open_scene(fifo)
    assert time.monotonic() - started < 5
    proc, rss = _cli_peak("show", "/dev/zero")
    assert proc.returncode == 1 and _errors(proc) == [
        "/dev/zero: error: file: not a regular file (a device or a pipe): not read"
    ]
    assert rss < 512  # it read until 7 GB
    del err2


# --- meshes, objects, nesting ----------------------------------------------------------------


def _shape(handle: int, pool_index: int = 0) -> bytes:
    wrapper = chunk("Mas", floats(1.0)) + b"EOO"
    mesh = chunk("Vev", ints(pool_index)) + chunk("Inv", ints(pool_index)) + b"EOO"
    own = [chunk("Ge2", chunk("Gst", wrapper + mesh) + b"EOO")]
    return scene_object("SHP", handle, f"s{handle}", own)


def _pool(vertices: int) -> bytes:
    verts = floats(*([0.5] * (3 * vertices)))
    tris = ints(*[i % vertices for i in range(3 * vertices)])
    return chunk("VIN", chunk("Ver", verts) + chunk("Ind", tris) + b"EOO")


def test_meshes_sharing_a_pool_array_share_its_numbers_and_count_against_a_bound(tmp_path):
    path = tmp_path / "shared.ttt"
    path.write_bytes(ttt_file(_pool(4) + _shape(1) + _shape(2)))
    a, b = (o.shape.meshes[0] for o in load_scene(path).objects)
    assert a.vertices is b.vertices and a.indices is b.indices and len(a.vertices) == 12
    # 20,000 numbers referred to by 250 shapes: 5 million numbers from an 80 KB pool
    path.write_bytes(ttt_file(_pool(3334) + b"".join(_shape(h) for h in range(1, 251))))
    err, peak = _peak(lambda: load_scene(path))
    assert isinstance(err, SceneError) and err.obj.startswith("s")
    assert err.message.startswith(
        f"the scene's meshes hold more than {limits.MAX_MESH_VALUES:,} numbers in all"
    )
    assert peak < 64, peak


def _nested_xml(depth: int) -> str:
    opening = "".join(f"<dummy><common><name>d{i}</name></common>" for i in range(depth))
    return (
        '<?xml version="1.0"?>\n<CoppeliaSim><filetype>simpleScene</filetype>'
        + opening
        + "</dummy>" * depth
        + "</CoppeliaSim>\n"
    )


def test_objects_nested_deeper_than_the_bound_are_one_clear_error(tmp_path):
    deep = tmp_path / "deep.simscene.xml"
    deep.write_text(_nested_xml(1000), encoding="utf-8")  # was a RecursionError traceback
    proc, _rss = _cli_peak("show", str(deep))
    assert proc.returncode == 1 and _errors(proc) == [
        f"{deep}: error: d{limits.MAX_DEPTH + 1}: objects nested more than "
        f"{limits.MAX_DEPTH} deep (course scenes nest 24 at most)"
    ]
    chain = b"".join(
        scene_object("DMY", h, f"d{h}", [], parent=h - 1 if h > 1 else -1) for h in range(1, 1001)
    )
    (tmp_path / "deep.ttt").write_bytes(ttt_file(chain))
    with pytest.raises(SceneError, match=f"nested more than {limits.MAX_DEPTH} deep"):
        load_scene(tmp_path / "deep.ttt")
    # at the bound, every form works: the readers, the report, the XML writer, the World plan
    ok = tmp_path / "ok.simscene.xml"
    ok.write_text(_nested_xml(limits.MAX_DEPTH + 1), encoding="utf-8")
    scene = load_scene(ok)
    assert json_report(scene).count('"path": "/d0/d1') == limits.MAX_DEPTH
    last = text_report(scene).splitlines()[3 + limits.MAX_DEPTH]
    assert last.startswith(" " * 64 + f"[level {limits.MAX_DEPTH}] d{limits.MAX_DEPTH} [")
    from sims.scene.build import _Planner
    from sims.scene.xml_write import write_xml

    assert write_xml(scene).count("<dummy>") == limits.MAX_DEPTH + 1
    assert len(_Planner(scene).full) == limits.MAX_DEPTH + 1


def test_a_parent_loop_is_broken_and_everything_is_listed(tmp_path):
    loop = scene_object("DMY", 1, "a", [], parent=2) + scene_object("DMY", 2, "b", [], parent=1)
    path = tmp_path / "loop.ttt"
    path.write_bytes(ttt_file(loop + scene_object("DMY", 3, "c", [], parent=1)))
    scene = load_scene(path)
    assert [(o.name, o.parent) for o in scene.objects] == [("a", None), ("b", None), ("c", 1)]
    assert {n.where for n in scene.notes if "parent loop" in n.message} == {"a", "b"}
    assert '"path": "/a/c"' in json_report(scene)
    x, y = SceneObject(1, "x", "dummy", parent=2), SceneObject(2, "y", "dummy", parent=1)
    looped = Scene(objects=(x, y))
    assert looped.path(looped.objects[0]) == "/y/x"  # a model built by hand: ends, not loops
    assert "x [1] (parent 2 in a loop)" in text_report(looped)


def test_showing_a_scene_takes_time_linear_in_its_objects():
    """Each report's time for 8,000 objects over its time for 2,000: 4 when linear, 16 when
    quadratic (16k objects took 10 s, 200k more than 4 minutes); best of three runs each."""

    def flat(n: int) -> Scene:
        kids = [SceneObject(i, f"d{i}", "dummy", parent=0) for i in range(1, n)]
        return Scene(objects=(SceneObject(0, "root", "dummy"), *kids))

    def best(fn, scene: Scene) -> float:
        times = []
        for _ in range(3):
            fresh = Scene(objects=scene.objects)  # no index built yet
            started = time.perf_counter()
            fn(fresh)
            times.append(time.perf_counter() - started)
        return min(times)

    small, large = flat(2000), flat(8000)
    for report in (text_report, json_report):
        ratio = best(report, large) / best(report, small)
        assert ratio < 8, (report.__name__, ratio)


def test_an_xml_file_of_empty_elements_is_refused_within_bounded_memory():
    from sims.scene.xml import read_xml

    flood = b"<CoppeliaSim>" + b"<x/>" * (limits.MAX_XML_ITEMS + 1) + b"</CoppeliaSim>"
    err, peak = _peak(lambda: read_xml(flood, "flood.simscene.xml"))
    assert isinstance(err, SceneError) and err.obj == "line 1"
    assert err.message.startswith(f"more than {limits.MAX_XML_ITEMS:,} XML elements")
    assert peak < 128, peak  # a 32 MB file of them held 680 MB


def test_object_count_and_compound_nesting_have_bounds(tmp_path, monkeypatch):
    """The bounds themselves (lowered here, so that the files stay small)."""
    monkeypatch.setattr(limits, "MAX_OBJECTS", 50)
    many = b"".join(scene_object("DMY", h, f"d{h}", []) for h in range(1, 52))
    (tmp_path / "many.ttt").write_bytes(ttt_file(many))
    with pytest.raises(SceneError, match="more than 50 objects in one scene"):
        load_scene(tmp_path / "many.ttt")
    xml = "".join(f"<dummy><common><name>d{i}</name></common></dummy>" for i in range(51))
    (tmp_path / "many.simscene.xml").write_text(
        f"<CoppeliaSim><filetype>simpleScene</filetype>{xml}</CoppeliaSim>", encoding="utf-8"
    )
    with pytest.raises(SceneError, match="more than 50 objects in one scene"):
        load_scene(tmp_path / "many.simscene.xml")
    from sims.scene import ttt_shapes, xml_shapes

    monkeypatch.setattr(xml_shapes, "MAX_COMPOUND_DEPTH", 3)
    nested = "<compound>" * 5 + "<primitive><type>cuboid</type></primitive>" + "</compound>" * 5
    (tmp_path / "deep.simscene.xml").write_text(
        "<CoppeliaSim><filetype>simpleScene</filetype><shape><common><name>s</name></common>"
        f"{nested}</shape></CoppeliaSim>",
        encoding="utf-8",
    )
    with pytest.raises(SceneError, match="compound shapes nested more than 3 deep"):
        load_scene(tmp_path / "deep.simscene.xml")
    assert ttt_shapes.MAX_COMPOUND_DEPTH == limits.MAX_COMPOUND_DEPTH == 64
