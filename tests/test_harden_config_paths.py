"""Files and folders that sitegen.yml names are inside the project (docs/security.md): one
outside is an error naming sitegen.yml, the line and the field, and nothing is read from it."""

from __future__ import annotations

from pathlib import Path

import pytest
from sitegen_helpers import run_cli, write_tree

from sitegen.config import parse_config
from sitegen.errors import BuildError

CLIP = "sims:\n  clips:\n    - {name: c, script: run.py, scene: 2w1a"


def _problems(text: str, root: Path) -> list[tuple[int | None, str, str]]:
    with pytest.raises(BuildError) as caught:
        parse_config(text, root, file="sitegen.yml")
    return [(d.line, d.field, d.message) for d in caught.value.diagnostics]


@pytest.mark.parametrize(
    ("text", "line", "field"),
    [
        ("title: t\nrosters:\n  - {name: g, file: /tmp/roster.txt}\n", 3, "rosters[0].file"),
        ("rosters:\n  - name: g\n    file: r.txt\n    corrections: ../c.yml\n", 4,
         "rosters[0].corrections"),
        ("rosters:\n  - {name: g, file: r.txt, aliases: ../../a.yml}\n", 2, "rosters[0].aliases"),
        ("content_dir: ../elsewhere\n", 1, "content_dir"),
        ("templates_dir: /etc\n", 1, "templates_dir"),
        ("sims:\n  clips:\n    - {name: c, script: ../run.py, scene: 2w1a}\n", 3,
         "sims.clips[0].script"),
        (CLIP.replace("2w1a", "/tmp/x.ttt") + "}\n", 3, "sims.clips[0].scene"),
        (CLIP + ", keys: ../k.txt}\n", 3, "sims.clips[0].keys"),
        (CLIP + ", python: ../venv/bin/python}\n", 3, "sims.clips[0].python"),
        ("sims:\n  sweeps:\n    - {name: s, script: /x/run.py, scene: 2w1a, seeds: '0:2'}\n", 3,
         "sims.sweeps[0].script"),
    ],
)  # fmt: skip
def test_a_path_out_of_the_project_is_an_error_at_its_line(tmp_path, text, line, field):
    project = write_tree(tmp_path / "p", {"run.py": "", "r.txt": ""})
    [(found_line, found_field, message)] = _problems(text, project)
    assert (found_line, found_field) == (line, field)
    assert "must be a path inside the project" in message


def test_a_symlink_out_of_the_project_is_outside_it(tmp_path):
    outside = write_tree(tmp_path / "outside", {"roster.txt": "g\t40823101\t40823101\n"})
    project = write_tree(tmp_path / "p", {"content/index.md": "# Home\n"})
    (project / "data").symlink_to(outside, target_is_directory=True)
    [(line, field, _message)] = _problems("rosters:\n  - {name: g, file: data/roster.txt}\n",
                                          project)  # fmt: skip
    assert (line, field) == (2, "rosters[0].file")


def test_paths_inside_names_and_the_output_folder_are_fine(tmp_path):
    project = write_tree(tmp_path / "p", {"run.py": "", "data/r.txt": ""})
    config = parse_config(
        "output_dir: ../site\n"  # written, not read: the site may go anywhere
        "rosters:\n  - {name: g, file: data/../data/r.txt}\n"
        f"{CLIP}, python: python3}}\n",  # a command name, a bundled scene name
        project,
    )
    assert config.rosters[0].file == project / "data/../data/r.txt"
    assert config.sims is not None and config.sims.clips[0].scene == "2w1a"


def test_the_build_stops_naming_the_file_and_line(tmp_path):
    outside = write_tree(tmp_path / "secret", {"roster.txt": "g\t40823101\t40823101\n"})
    project = write_tree(
        tmp_path / "p",
        {
            "sitegen.yml": f"title: t\nrosters:\n  - name: g\n    file: {outside / 'roster.txt'}\n",
            "content/index.md": "# Home\n",
        },
    )
    proc = run_cli("build", "--source", str(project), "--output", str(tmp_path / "site"))
    assert proc.returncode == 1
    assert "sitegen.yml:4: error: rosters[0].file: must be a path inside the project" in (
        proc.stderr
    )
    assert not (tmp_path / "site").exists()
