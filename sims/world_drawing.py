"""Drawing a World: its renderer and a scene file's visual-only bodies (a mixin of World).

Apart from the stepping core (sims/world.py) so each file says what it holds; the renderer
itself is sims/render.py.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from sims.models.common import SceneModel
from sims.quiet import pybullet as p


class WorldDrawing:
    """Renderer access and visual bodies; World supplies the client and link frames."""

    model: SceneModel
    _renderer: Any

    if TYPE_CHECKING:  # supplied by World

        @property
        def _cid(self) -> int: ...

        def link_frame(self, body: int, link: int) -> tuple: ...

    def render(
        self, width: int, height: int, follow: str | None = None, camera: Any = None
    ) -> np.ndarray:
        """HxWx3 uint8 RGB from a chase camera on ``follow`` (default: the scene's robot), or
        from ``camera``: (view, projection) matrices (sims.camera's fixed overview)."""
        self.sync_visuals()
        if self._renderer is None:
            from sims.render import Renderer

            self._renderer = Renderer(self, prefer="tinyrenderer")
        return self._renderer.render(width, height, follow or self.model.robot, camera)

    def sync_visuals(self) -> None:
        """Put a scene file's visual-only bodies on their links (done before drawing only)."""
        c = self._cid
        data = self.model.data
        if "looks" in data and "visuals" not in data:
            from sims.scene.bodies import create_visuals

            data["visuals"] = create_visuals(c, data["looks"])
        for v in data.get("visuals", ()):
            pos, orn = self.link_frame(v.body, v.link)
            pos, orn = p.multiplyTransforms(pos, orn, *v.offset)
            p.resetBasePositionAndOrientation(v.uid, pos, orn, physicsClientId=c)

    def new_render_sequence(self) -> None:
        """Frames drawn from now on start a new sequence (a clip's frame range): the renderer
        draws its first frame at a size twice (sims/render.py)."""
        if self._renderer is not None:
            self._renderer.new_sequence()

    @property
    def renderer(self) -> str:
        """Which renderer ran (or will run): "egl" or "tinyrenderer"."""
        return "tinyrenderer" if self._renderer is None else self._renderer.name

    @property
    def renderer_fallback(self) -> str | None:
        """Why EGL was asked for and TinyRenderer runs instead (None: no fallback)."""
        return None if self._renderer is None else self._renderer.fallback_reason
