"""sitegen: a static course-site generator with a simulation gallery."""

__version__ = "0.1.0"

# The distribution's name, as pip knows it ("sitegen" on PyPI is another project's); the
# command and the import packages are `sitegen`.
DISTRIBUTION = "sitegen-course"

# Where a site made by `sitegen new` has its CI install sitegen from: this project's repository,
# pinned to the tag of this version (`sitegen.scaffold.requirement`). Set it to the project's
# public address when it has one; `sitegen new --from SPEC` names any other source.
REPOSITORY = "https://github.com/OWNER/REPO"
RELEASE_TAG = f"v{__version__}"
