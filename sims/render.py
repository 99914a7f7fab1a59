"""Headless frames from a World: a chase camera and the choice between EGL and TinyRenderer.

pybullet's EGL plugin (``eglRenderer``) renders with OpenGL through Mesa (llvmpipe on a machine
without a GPU); TinyRenderer is pybullet's built-in CPU rasteriser. EGL is used only when
asked for (``World(render_with="egl"|"auto")``; the clip worker passes ``SIMS_RENDERER``); any
failure (no plugin, no EGL display, a blank first frame) falls back to TinyRenderer, and
``Renderer.name`` / ``World.renderer`` say which one ran. The default
is decided in ``DEFAULT_RENDERER`` from measurements recorded in docs/sims.md.

Why EGL fell back is decided here alone (``Renderer.fallback_reason``, read as
``World.renderer_fallback``) and said to the user in one line made by :func:`fallback_note`,
once per build or recording: TinyRenderer is several times slower, so a user whose clips take
minutes should learn why.
"""

from __future__ import annotations

import os
import pkgutil
import weakref
from collections.abc import Iterable
from typing import Any, Protocol

import numpy as np

from sims.quiet import pybullet as p
from sims.quiet import quiet_fd


class World(Protocol):
    """What a Renderer reads of ``sims.world.World`` (which creates it: a Protocol, so
    that this module does not import the world back)."""

    client_id: int
    model: Any
    _client: int | None

    def object_pose(self, handle: Any) -> tuple: ...


DEFAULT_RENDERER = "auto"  # EGL if it works, else TinyRenderer; see docs/sims.md
FOV_DEG, NEAR, FAR = 50.0, 0.01, 20.0
LIGHT_DIRECTION = (0.4, -0.6, 1.0)
# The EGL plugin keeps process-wide state: a second World loading it makes the first one's
# frames wrong (measured), so only one live World per process may use EGL; others fall back.
_egl_owner: weakref.ref[Renderer] | None = None


Matrices = tuple[list[float], list[float]]  # pybullet's view and projection matrices


def chase_camera(world: World, width: int, height: int, follow: str) -> Matrices:
    """The chase camera's matrices: the scene's camera offset, looking at ``follow``."""
    cam = world.model.camera
    pos, _ = world.object_pose(follow)
    target = (pos[0], pos[1], cam.target_z)
    view = p.computeViewMatrixFromYawPitchRoll(target, cam.distance, cam.yaw, cam.pitch, 0.0, 2)
    proj = p.computeProjectionMatrixFOV(FOV_DEG, width / height, NEAR, FAR)
    return view, proj


def requested_renderer() -> str:
    """The renderer asked for by ``SIMS_RENDERER`` ("egl", "tinyrenderer", "auto")."""
    value = os.environ.get("SIMS_RENDERER", DEFAULT_RENDERER).strip().lower()
    return {"tiny": "tinyrenderer", "": DEFAULT_RENDERER}.get(value, value)


def fallback_note(reasons: Iterable[str | None]) -> str | None:
    """The one line telling the user why frames were drawn with TinyRenderer although EGL was
    asked for (each distinct reason once), or None when nothing fell back."""
    found = sorted({reason for reason in reasons if reason})
    if not found:
        return None
    return "clips rendered with TinyRenderer (slower): " + "; ".join(found)


class Renderer:
    """Renders a World's scene; owns the EGL plugin for that World's client when it uses it.

    Created by the World before it builds the scene when EGL is wanted, because the plugin only
    converts visual shapes created after it is loaded (a plugin loaded later renders an empty
    scene). ``verify()`` runs once the scene exists and falls back on a blank frame.
    """

    def __init__(self, world: World, prefer: str = "tinyrenderer"):
        self.world = world
        self.name = "tinyrenderer"
        self.fallback_reason: str | None = None
        self._plugin = -1
        self._last_size: tuple[int, int] | None = None
        if prefer in ("egl", "auto"):
            self._load_egl()

    def _load_egl(self) -> None:
        global _egl_owner
        if _egl_owner is not None and _egl_owner() is not None:
            self.fallback_reason = "EGL is already used by another World in this process"
            return
        loader = pkgutil.get_loader("eglRenderer")
        if loader is None:
            self.fallback_reason = "eglRenderer plugin not found"
            return
        with quiet_fd(1), quiet_fd(2):
            plugin = p.loadPlugin(
                loader.get_filename(),
                "_eglRendererPlugin",  # type: ignore[attr-defined]
                physicsClientId=self.world.client_id,
            )
        if plugin < 0:
            self.fallback_reason = "could not load the EGL plugin"
            return
        self._plugin = plugin
        self.name = "egl"
        _egl_owner = weakref.ref(self)

    def verify(self) -> None:
        """Render one small frame; an EGL context that draws nothing falls back to TinyRenderer."""
        if self.name != "egl":
            return
        with quiet_fd(1):  # the plugin prints driver details on its first frame
            frame = self.render(64, 48, self.world.model.robot)
        if int(frame.max()) - int(frame.min()) < 8:
            self.close()
            self.name = "tinyrenderer"
            self.fallback_reason = "EGL rendered a blank frame"

    def new_sequence(self) -> None:
        """The next frame starts a run of frames rendered in order (a clip's frame range): it
        is drawn twice under EGL, so it never depends on what this process drew before."""
        self._last_size = None

    def scene_rebuilt(self) -> None:
        """Called after World.reset(): the plugin survives resetSimulation and sees the rebuild."""

    def close(self) -> None:
        global _egl_owner
        if self._plugin >= 0 and not self.world.closed:
            with quiet_fd(1), quiet_fd(2):
                p.unloadPlugin(self._plugin, physicsClientId=self.world.client_id)
        if self._plugin >= 0:
            _egl_owner = None
        self._plugin = -1

    def render(
        self, width: int, height: int, follow: str, camera: Matrices | None = None
    ) -> np.ndarray:
        """A frame from the chase camera on ``follow``, or from ``camera`` (view, projection)."""
        world = self.world
        view, proj = camera or chase_camera(world, width, height, follow)
        engine = p.ER_BULLET_HARDWARE_OPENGL if self.name == "egl" else p.ER_TINY_RENDERER
        # EGL's first frame at a new size differs from the following ones (measured; the
        # shadow pass lags a frame), so that frame is drawn twice to keep clips uniform.
        repeats = 2 if self.name == "egl" and (width, height) != self._last_size else 1
        self._last_size = (width, height)
        with quiet_fd(1), quiet_fd(2):  # EGL prints driver details whenever the size changes
            for _ in range(repeats):
                img = p.getCameraImage(
                    width,
                    height,
                    view,
                    proj,
                    renderer=engine,
                    lightDirection=LIGHT_DIRECTION,
                    shadow=1,
                    flags=p.ER_NO_SEGMENTATION_MASK,
                    physicsClientId=world.client_id,
                )
        rgba = np.asarray(img[2], dtype=np.uint8).reshape(height, width, 4)
        return np.ascontiguousarray(rgba[:, :, :3])
