"""simIK environments (CoppeliaSim 4.2+'s IK plugin) over a World: IK groups a script builds
from the scene's objects instead of the groups saved with the scene (sims/kinematics.py solves
both the same way)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from sims.kinematics import GroupState, Kinematics, _matrix
from sims.scene.model import IkElement, IkGroup
from sims.scene.model_mech import IK_ALPHA_BETA, IK_GAMMA, IK_X, IK_Y, IK_Z


class IkEnvironment(Kinematics):
    """A simIK environment (CoppeliaSim 4.2+'s IK plugin) over the World: groups made by the
    script from the scene's objects (``simIK.addIkElementFromScene``), every joint between an
    element's base and tip taking part; ``handle_group`` solves and, as
    ``simIK.applyIkEnvironmentToScene`` does, writes the joint values to the scene."""

    def create_group(self, name: str = "") -> int:
        """simIK.createIkGroup: an empty group (pseudo-inverse, 3 iterations) and its handle."""
        handle = max(self.groups, default=0) + 1
        group = IkGroup(name=name or f"IK group {handle}", handle=handle, explicit=True)
        self.groups[handle] = GroupState(group, True, True)
        return handle

    def add_element_from_scene(
        self, group: int, base: int | str | None, tip: int | str, target: int | str,
        constraints: int = IK_X | IK_Y | IK_Z | IK_ALPHA_BETA | IK_GAMMA,
    ) -> int:  # fmt: skip
        """simIK.addIkElementFromScene: tip onto target over the joints from base; returns
        the element's handle (its index in the group, from 1)."""
        w = self.world
        state = self._state(group)
        element = IkElement(
            tip=w.handle_of(tip),
            base=None if base in (None, -1) else w.handle_of(base),
            constraints=int(constraints),
            target=w.handle_of(target),
            all_joints=True,
        )
        state.group = replace(state.group, elements=(*state.group.elements, element))
        return len(state.group.elements)

    def set_group_calculation(
        self, group: int, method: str, damping: float = 0.1, iterations: int = 3
    ) -> None:
        """simIK.setIkGroupCalculation (method: one of IkGroup's)."""
        state = self._state(group)
        state.group = replace(
            state.group, method=method, damping=float(damping), iterations=max(1, int(iterations))
        )

    def set_element_precision(
        self, group: int, element: int, linear: float, angular: float
    ) -> None:
        state = self._state(group)
        items = list(state.group.elements)
        items[element - 1] = replace(items[element - 1], precision=(linear, angular))
        state.group = replace(state.group, elements=tuple(items))

    def handle_group(self, group: int) -> int:
        """simIK.handleIkGroup + applyIkEnvironmentToScene: solve and write the joints."""
        return self.handle(group)

    def set_element_weights(self, group: int, element: int, linear: float, angular: float) -> None:
        self._element(group, element, weights=(float(linear), float(angular)))

    def set_element_constraints(self, group: int, element: int, constraints: int) -> None:
        self._element(group, element, constraints=int(constraints))

    def _element(self, group: int, element: int, **changes: object) -> None:
        state = self._state(group)
        items = list(state.group.elements)
        if not 1 <= element <= len(items):
            raise KeyError(f"IK group {group} has no element {element}")
        items[element - 1] = replace(items[element - 1], **changes)  # type: ignore[arg-type]
        state.group = replace(state.group, elements=tuple(items))

    def joint_names(self, group: int) -> list[str]:
        """The joints between the group's elements' bases and tips (what the group moves)."""
        names: list[str] = []
        for e in self._state(group).group.elements:
            chain = self._chain(e)
            for n in chain.joints if chain is not None else ():
                if n not in names:
                    names.append(n)
        return names

    def solve(
        self, group: int, start: dict[str, float], only: list[str]
    ) -> tuple[dict[str, float], bool] | None:
        """One resolution of ``group`` (its method and iterations) from the joint values
        ``start``, over the joints ``only``, without touching the scene: the new values and
        whether every tip is within its precision (None: nothing to solve)."""
        state = self._state(group)
        elements = [e for e in state.group.elements if e.enabled]
        if not state.enabled or not elements:
            return None
        return self._solve(state.group, elements, start, only=only)

    def tip_errors(self, group: int, values: dict[str, float]) -> tuple[float, float]:
        """The largest linear (m) and angular (rad) distance between a tip and its target at
        joint values ``values`` (simIK.handleGroup's precision)."""
        lin = ang = 0.0
        for e in self._state(group).group.elements:
            chain = self._chain(e)
            if chain is None:
                continue
            q = np.array([values.get(n, v) for n, v in zip(chain.joints, chain.q, strict=True)])
            tip = chain.frames(q)[1]
            target = _matrix(self.world.object_pose(self._target(e)))
            lin = max(lin, float(np.linalg.norm(target[:3, 3] - tip[:3, 3])))
            cos = (np.trace(target[:3, :3] @ tip[:3, :3].T) - 1) / 2
            ang = max(ang, float(np.arccos(np.clip(cos, -1.0, 1.0))))
        return lin, ang
