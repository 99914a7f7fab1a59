"""Issue 15, item 2: one bounded YAML loader (located.yaml) for front matter, sitegen.yml and
roster corrections; an alias bomb is a clear error naming file and line (docs/security.md)."""

from __future__ import annotations

import resource
import sys
from pathlib import Path

import pytest
from sitegen_helpers import run_cli, write_tree

from located import yaml as located_yaml
from roster import load_roster


def _bomb(levels: int = 9, indent: str = "") -> str:
    """The "billion laughs" document: each line names the previous one nine times."""
    names = "abcdefghijklmnop"
    lines = [f"{indent}{names[0]}: &{names[0]} [x, x, x, x, x, x, x, x, x]"]
    for i in range(1, levels):
        refs = ", ".join([f"*{names[i - 1]}"] * 9)
        lines.append(f"{indent}{names[i]}: &{names[i]} [{refs}]")
    return "\n".join(lines) + "\n"


def _limited_memory() -> None:  # pragma: no cover (runs in the child before exec)
    resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))


def _build_bounded(src: Path, out: Path):
    """A build in a child with 3 GiB of address space and a minute: an unbounded loader
    fails here by running out of either."""
    import subprocess

    return subprocess.run(
        [sys.executable, "-m", "sitegen", "build", "--source", str(src), "--output", str(out)],
        capture_output=True,
        text=True,
        timeout=60,
        preexec_fn=_limited_memory,
    )


def test_alias_bomb_in_front_matter_is_an_error_with_file_and_line(tmp_path):
    page = "---\n" + _bomb() + "title: *i\n---\n# Page\n"
    src = write_tree(tmp_path / "src", {"index.md": "# Home\n", "bomb.md": page})
    result = _build_bounded(src, tmp_path / "site")
    assert result.returncode == 1, result.stderr[-500:]
    assert "Traceback" not in result.stderr
    # line 7 of the file: the seventh line of YAML is where the expansion passes the limit
    assert "bomb.md:7: error: front matter: YAML expands to more than 100000 values" in (
        result.stderr
    )


def test_alias_bomb_in_sitegen_yml_is_an_error_with_file_and_line(tmp_path):
    src = write_tree(
        tmp_path / "proj",
        {
            "sitegen.yml": "sims:\n  clips: []\n" + _bomb() + "title: *i\n",
            "content/index.md": "# H\n",
        },
    )
    result = _build_bounded(src, tmp_path / "site")
    assert result.returncode == 1, result.stderr[-500:]
    assert "Traceback" not in result.stderr
    assert (
        f"{src / 'sitegen.yml'}:8: error: YAML expands to more than 100000 values" in result.stderr
    )


def test_roster_corrections_go_through_the_same_bounded_loader(tmp_path):
    roster = tmp_path / "r.txt"
    roster.write_text("1\tx1\n", encoding="utf-8")
    corrections = tmp_path / "r.corrections.yml"
    corrections.write_text("typos:\n" + "".join(f"  w{i}: v{i}\n" for i in range(80_000)))
    assert corrections.stat().st_size > located_yaml.MAX_BYTES
    result = load_roster(roster, corrections=corrections)
    errors = [(d.line, d.message) for d in result.errors if d.file == str(corrections)]
    assert len(errors) == 1 and errors[0][0] == 1
    assert errors[0][1].startswith("YAML document is ")
    assert errors[0][1].endswith(f"bytes; the limit is {located_yaml.MAX_BYTES}")


@pytest.mark.parametrize(
    "text, line, message",
    [
        (_bomb(), 6, "YAML expands to more than 100000 values"),
        ("".join(f"k{i}: &a{i} x\n" for i in range(101)) + "all: [" + ", ".join(
            f"*a{i}" for i in range(101)) + "]\n", 102, "more than 100 YAML aliases"),
        ("x: " + "[" * 65 + "]" * 65 + "\n", 1, "nest more than 64 levels deep"),
        ("a: [\n", 2, "YAML syntax error"),
    ],
)  # fmt: skip
def test_limits_and_syntax_errors_name_the_line(text, line, message):
    with pytest.raises(located_yaml.YamlError) as info:
        located_yaml.compose(text, "f.yml", first_line=1)
    assert (info.value.file, info.value.line) == ("f.yml", line)
    assert message in info.value.message


def test_documents_within_the_limits_load_with_their_lines():
    text = "base: &base {fps: 20}\nclips:\n  - {<<: *base, name: one}\n  - {<<: *base, name: two}\n"
    node = located_yaml.compose(text, "f.yml", first_line=3)
    assert located_yaml.line_of(node.value[1][0], first_line=3) == 4
    assert located_yaml.to_python(node)["clips"][1] == {"fps": 20, "name": "two"}
    assert located_yaml.load("", "empty.yml") is None


def test_wrong_values_are_quoted_short_in_messages(tmp_path):
    huge = "[" + ", ".join(["word"] * 5000) + "]"
    src = write_tree(
        tmp_path / "src", {"index.md": "# Home\n", "p.md": f"---\ntitle: {huge}\n---\n# P\n"}
    )
    result = run_cli("build", "--source", str(src), "--output", str(tmp_path / "site"))
    line = next(x for x in result.stderr.splitlines() if x.startswith("p.md:2:"))
    assert "title: must be text, got ['word', 'word', 'word', 'word', ...]" in line
    assert len(line) < 200


def test_a_clip_time_limit_must_be_positive_and_at_most_a_week(tmp_path):
    from sitegen.config import parse_config
    from sitegen.errors import BuildError

    for value in ("-1", "1.0e+308"):  # 1e308 overflowed the clocks waiting on it
        with pytest.raises(BuildError) as info:
            parse_config(f"sims:\n  timeout: {value}\n", tmp_path)
        assert [(d.line, d.field, d.message) for d in info.value.diagnostics] == [
            (2, "sims.timeout", "must be a positive number of seconds, at most 604800 (a week)")
        ]


def test_front_matter_duplicate_keys_are_errors_at_their_lines(tmp_path):
    """Front matter goes through the same walker as sitegen.yml: a second ``title:`` is an
    error at its line (YAML alone would keep the later one silently), as in sitegen.yml."""
    src = write_tree(
        tmp_path / "src",
        {"content/index.md": "---\ntitle: First\nweight: 1\ntitle: Second\n---\n# Home\n"},
    )
    run = run_cli("build", "--source", str(src), "--output", str(tmp_path / "o"))
    assert run.returncode == 1
    assert "index.md:4: error: title: duplicate key 'title' (first at line 2)" in run.stderr
    assert "Traceback" not in run.stderr
