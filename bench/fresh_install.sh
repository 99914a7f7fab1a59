#!/usr/bin/env bash
# A new user's install, in full (downloads every dependency): a fresh virtual environment with
# nothing in it, `pip install` of SPEC (default: this checkout; e.g. git+file:///path/to/clone),
# then `sitegen new s && cd s && sitegen build --strict && sitegen check site`, then the new
# site's own workflow steps (.github/workflows/*.yml `run:` steps, sudo lines left out), which
# install sitegen again from the requirements.txt that `sitegen new --from SPEC` wrote.
#   bash bench/fresh_install.sh [SPEC] [PYTHON]
# tests/test_install.py does the same from a wheel without downloading anything.
set -euo pipefail
repo="$(cd "$(dirname "$0")/.." && pwd)"
spec="${1:-$repo}"
python="${2:-python3}"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
start=$(date +%s)
"$python" -m venv "$work/venv"
# shellcheck disable=SC1091
. "$work/venv/bin/activate"
python -m pip install -q --disable-pip-version-check "$spec"
echo "installed $(python -m pip show sitegen-course | grep -E '^(Name|Version|Location)' | tr '\n' ' ')in $(($(date +%s) - start)) s"
cd "$work"
sitegen new s --from "$spec"
cd s
sitegen build --strict
sitegen check site
python - <<'PY'
import subprocess, yaml, pathlib
for wf in sorted(pathlib.Path(".github/workflows").glob("*.yml")):
    for job in yaml.safe_load(wf.read_text())["jobs"].values():
        for step in job["steps"]:
            if "run" in step:
                lines = [l for l in step["run"].splitlines() if not l.lstrip().startswith("sudo ")]
                subprocess.run(["bash", "-eo", "pipefail", "-c", "\n".join(lines)], check=True)
                print(f"{wf.name}: {step.get('name', 'step')}: ok")
PY
echo "fresh install, new site, strict build, check, workflow steps: all passed in $(($(date +%s) - start)) s"
