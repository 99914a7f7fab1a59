"""Print the site half's requirements from pyproject.toml, one a line (for .ci/matrix)."""

import re
from pathlib import Path

import tomllib

SITE = {"jinja2", "markdown", "pygments", "pymdown-extensions", "pyyaml", "regex", "rich"}

project = tomllib.loads((Path(__file__).parents[1] / "pyproject.toml").read_text())["project"]
for requirement in project["dependencies"]:
    if re.split(r"[<>=!~ \[;]", requirement, maxsplit=1)[0].lower() in SITE:
        print(requirement)
