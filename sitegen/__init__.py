"""sitegen: a static course-site generator with a simulation gallery."""

__version__ = "0.1.0"
