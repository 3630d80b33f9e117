"""Exceptions and warnings raised by pinograsp.

Every error pinograsp raises derives from :class:`PinograspError`. Subclasses carry the
culprit (a contact, joint, actuator, file or value) as attributes so that callers can react
programmatically, and their messages name it so that users can fix their input.
"""

from __future__ import annotations

from collections.abc import Iterable


class PinograspError(Exception):
    """Root of every error raised by pinograsp."""


class InvalidInputError(PinograspError, ValueError):
    """A user-supplied value is malformed (NaN, wrong shape, out of range, ...).

    Attributes:
        name: Name of the offending argument or item (e.g. ``"wrench"``, ``"contact 3"``).
        value: The offending value, when it is small enough to keep.
    """

    def __init__(self, name: str, message: str, value: object = None) -> None:
        self.name = name
        self.value = value
        super().__init__(f"{name}: {message}")


def plural(kind: str, count: int | None = None) -> str:
    """The plural of a kind of name in a message (``"wrench axis"`` -> ``"wrench axes"``); with
    ``count``, the count and the word in the number it takes (``"1 value"``, ``"3 values"``)."""
    if count is not None:
        return f"{count} {kind if count == 1 else plural(kind)}"
    if kind.endswith("axis"):
        return kind[:-4] + "axes"
    return kind + ("es" if kind.endswith(("s", "x", "ch", "sh")) else "s")


class UnknownNameError(PinograspError, KeyError):
    """A name (joint, link, actuator, contact, scene, solver, ...) does not exist.

    Attributes:
        kind: What kind of name was looked up (``"joint"``, ``"actuator"``, ...).
        name: The unknown name.
        valid: The names that would have been accepted.

    ``hint`` (optional) says what else to pass, appended to the message.
    """

    def __init__(self, kind: str, name: object, valid: Iterable[object], hint: str = "") -> None:
        self.kind = kind
        self.name = name
        self.valid = list(valid)
        shown = ", ".join(repr(v) for v in self.valid[:40])
        more = "" if len(self.valid) <= 40 else f", ... ({len(self.valid)} in all)"
        listed = (
            f"valid {plural(kind)}: {shown}{more}"
            if self.valid
            else f"there are no {plural(kind)} to choose from"
        )
        super().__init__(f"unknown {kind} {name!r}; {listed}" + (f"; {hint}" if hint else ""))

    def __str__(self) -> str:  # KeyError would otherwise print the repr of the message
        return str(self.args[0])


class ModelError(PinograspError, ValueError):
    """A grasp model cannot be built from the given contacts, actuators and couplings.

    Attributes:
        argument: The argument of :meth:`~pinograsp.GraspModel.from_contacts` at fault
            (``"contacts"``, ``"joint_names"``, ``"planar"``, ``"actuators"``, ``"couplings"``),
            or ``None``.
    """

    def __init__(self, message: str, argument: str | None = None) -> None:
        super().__init__(message)
        self.argument = argument


class SolverError(PinograspError, RuntimeError):
    """An optimisation backend failed or returned an answer that did not pass the audit.

    Attributes:
        solver: Name of the backend.
        status: The backend's status string, when there is one.
    """

    def __init__(self, message: str, solver: str | None = None, status: str | None = None) -> None:
        self.solver = solver
        self.status = status
        super().__init__(message)


class SolverNotAvailableError(SolverError, ImportError):
    """The requested optimisation backend is not installed.

    The message names the package (or pinograsp extra) to install.
    """


class SolverTimeoutError(SolverError):
    """A solve hit its time limit before proving optimality or infeasibility."""


class PreloadNotInEquilibriumError(PinograspError):
    """The preload alone (``w = 0``) has no passive equilibrium.

    Raised by analyses that start from the preloaded grasp, instead of reporting that the
    grasp "resists 0 N". Attributes:
        command: The actuator command that failed, in actuator units.
        detail: What the equilibrium solve reported (with the residual net wrench).
        residual: The net wrench on the object (6,) [N, N·m], or None.
    """

    def __init__(
        self, command: object, detail: str, residual: object = None, method: str | None = None
    ) -> None:
        self.command = command
        self.detail = detail
        #: Net wrench left on the object at w = 0 (6,) [N, N·m], when the solve gives one.
        self.residual = residual
        #: The method whose preload stage refused the command (its equilibrium tolerance).
        self.method = method
        call = (
            "pg.equilibrium_preload(model)"
            if method is None
            else f"pg.equilibrium_preload(model, {method!r})"
        )
        super().__init__(
            f"preload not in equilibrium at w = 0 (command {command}): {detail}. "
            f"{call} finds commands that are, verified by the same method, or says why none exist "
            "(docs/hands.md, 'Choosing a preload')"
        )


class NoPreloadError(PreloadNotInEquilibriumError):
    """No preload exists (or none was verified) for the grasp: the contacts left cannot all be
    pressed by any admissible command, so there is no command to test for equilibrium.

    Distinct from its base, :class:`PreloadNotInEquilibriumError` ("this command does not
    balance"): here no command was found at all (``pg.equilibrium_preload`` reported
    ``status``). A subclass so that code catching the base keeps working. Attributes:
        status: ``pg.equilibrium_preload``'s status (``"infeasible"`` or ``"unverified"``), or
            ``None`` when no design was attempted (no actuator reaches a contact).
        unloadable_contacts: Contacts that no preload can press.
        unbalanced_actuators: Actuators whose command no preload can balance.
        contacts_detected: How many contacts the grasp has (the batch row's ``n_contacts``), or
            ``None`` when no contact model was built.
    """

    def __init__(
        self,
        detail: str,
        status: str | None = None,
        unloadable_contacts: Iterable[str] = (),
        unbalanced_actuators: Iterable[str] = (),
        contacts_detected: int | None = None,
    ) -> None:
        self.contacts_detected = contacts_detected
        self.method = None
        self.command = None
        self.detail = detail
        self.residual = None
        self.status = status
        self.unloadable_contacts = tuple(unloadable_contacts)
        self.unbalanced_actuators = tuple(unbalanced_actuators)
        PinograspError.__init__(
            self,
            "no preload exists for this grasp"
            + (f" (equilibrium_preload: {status})" if status else "")
            + f": {detail}. "
            "Move the object or the hand so that opposing contacts press, raise max_command, or "
            "see docs/hands.md, 'Choosing a preload'",
        )


class PinograspWarning(UserWarning):
    """Root of every warning issued by pinograsp."""


class BigMWarning(PinograspWarning):
    """A mixed-integer solution touched (or came close to) a big-M bound."""


class ConditioningWarning(PinograspWarning):
    """The model is scaled beyond what the default solver resolves reliably (e.g. a stiffness
    ratio above 1e5 between contacts): use the reference backend (``backend="miqp"``)."""


class RefinementWarning(PinograspWarning):
    """Friction-cone refinement stopped at its edge limit before reaching its tolerance."""


class AuditWarning(PinograspWarning):
    """A solution fails a physical check the optimisation does not impose: its springs store
    more energy than the load and the actuators supply (the wedging artefact of the PRP), or its
    displacements are absurdly large (``PassiveResponse.audit.energy``; docs/accuracy.md)."""


class ModelFileError(PinograspError, ValueError):
    """A model file (URDF, hand description, mesh) is missing, unreadable or malformed.

    Attributes:
        path: The offending file (as given, or as resolved).
        detail: What went wrong.
    """

    def __init__(self, path: object, detail: str) -> None:
        self.path = str(path)
        self.detail = detail
        super().__init__(f"{self.path}: {detail}")


class UrdfError(ModelFileError):
    """A URDF file cannot be loaded (malformed XML, missing mesh, unsupported joint, ...)."""


#: What to do about a :class:`NoContactError` at a given configuration.
NO_CONTACT_ADVICE = (
    "move the object (its pose in the hand base frame [m]) to within the tolerance of a link, or "
    "close the hand on it first (q = hand.close_on(obj))"
)


class NoContactError(PinograspError):
    """No hand collision geometry is within the contact tolerance of the object.

    Attributes:
        distances: Closest signed distance [m] of each hand link to the object.
        tolerance: The contact tolerance [m] that was used.
        surfaces: Links whose mesh (a surface, Coal BVH) contains the object's centre in its
            bounding box: the object may be inside the link, where no distance sees it.
        advice: What to do (the end of the message; not shown when ``surfaces`` says it).
    """

    def __init__(
        self,
        distances: dict[str, float],
        tolerance: float,
        surfaces: tuple[str, ...] = (),
        advice: str = NO_CONTACT_ADVICE,
    ) -> None:
        self.distances = dict(distances)
        self.tolerance = float(tolerance)
        self.surfaces = tuple(surfaces)
        self.advice = advice
        ordered = sorted(self.distances.items(), key=lambda kv: kv[1])
        shown = ", ".join(f"{k}: {v * 1e3:.3f} mm" for k, v in ordered)
        note = ""
        if self.surfaces:
            note = (
                f"; the object's centre lies within the mesh of {', '.join(self.surfaces)}: a hand mesh "
                "is a surface (Coal BVH), not a solid, so an object inside it reports its positive "
                "distance to the wall; move the object out of that link (docs/hands.md, mesh hands)"
            )
        super().__init__(
            f"the hand touches nothing (contact tolerance {self.tolerance * 1e3:.3f} mm); "
            f"closest signed distances per link: {shown or 'no collision geometry'}{note}"
            + (f"; {advice}" if advice and not self.surfaces else "")
        )

    def __reduce__(self) -> tuple:  # picklable (batch workers) with its attributes
        return (type(self), (self.distances, self.tolerance, self.surfaces, self.advice))


class PenetrationError(PinograspError):
    """Hand links penetrate the object deeper than allowed.

    Attributes:
        depths: Signed distance [m] (negative) of each offending link.
        max_penetration: The allowed penetration depth [m].
        distances: Closest signed distance [m] of every hand link.
    """

    def __init__(self, depths: dict[str, float], max_penetration: float, distances: dict[str, float]) -> None:
        self.depths = dict(depths)
        self.max_penetration = float(max_penetration)
        self.distances = dict(distances)
        shown = ", ".join(f"{k}: {v * 1e3:.3f} mm" for k, v in self.depths.items())
        super().__init__(
            f"deep penetration (more than {self.max_penetration * 1e3:.3f} mm) of links into the object: "
            f"{shown}; "
            "move the hand or the object, or pass a larger max_penetration [m] (default 5 mm) to "
            "close_on / grasp_model_from_scene (scene files: 'max_penetration')"
        )

    def __reduce__(self) -> tuple:  # picklable (batch workers) with its attributes
        return (type(self), (self.depths, self.max_penetration, self.distances))


class MissingDependencyError(PinograspError, ImportError):
    """An optional dependency needed for a feature is not installed.

    Attributes:
        package: The missing Python package (e.g. ``"plotly"``).
        extra: The pinograsp extra that installs it (e.g. ``"viz"``), when there is one.
    """

    def __init__(self, package: str, feature: str, extra: str | None = None) -> None:
        self.package = package
        self.extra = extra
        how = f'pip install "pinograsp[{extra}]"' if extra else f"pip install {package}"
        super().__init__(f"{feature} needs the optional package {package!r}: {how}")


class SceneError(InvalidInputError, ModelFileError):
    """A scene file (YAML) is missing, malformed or names something that does not exist.

    The message names the file and the key path inside it, e.g.
    ``case1.yaml: object.pose.xyz: expected 3 numbers, got 2``. Catchable as
    :class:`InvalidInputError` and as :class:`ModelFileError`.

    Attributes:
        path: The scene file (full path).
        key: Dotted key path inside the file (``""`` for the file as a whole).
        detail: What went wrong.
    """

    def __init__(self, path: object, key: str, detail: str) -> None:
        from pathlib import Path

        self.path = str(path)
        self.key = key
        self.detail = detail
        self.name = key
        self.value = None
        where = f"{Path(self.path).name}: {key}: " if key else f"{Path(self.path).name}: "
        Exception.__init__(self, where + detail)


class UnknownChoiceError(InvalidInputError, UnknownNameError):  # type: ignore[misc]  # name: both bases
    """A name that must be one of a registry's entries (a method, a backend) is not.

    Catchable as :class:`InvalidInputError` (a bad argument) and as :class:`UnknownNameError`
    (``kind``, ``name`` and ``valid`` list the registered names).
    """

    def __init__(self, kind: str, name: object, valid: Iterable[object]) -> None:
        self.kind = kind
        self.valid = list(valid)
        self.name = name  # type: ignore[assignment]  # the unknown name (UnknownNameError's meaning)
        self.value = name
        Exception.__init__(self, f"{kind}: must be one of {tuple(self.valid)}, got {name!r}")

    def __str__(self) -> str:
        return str(self.args[0])


class ContactDetectionError(PinograspError):
    """Contact detection found a hand–object pair it cannot turn into a contact (no usable
    normal or a non-finite point), named by object, hand link, geometry and pose.

    Attributes:
        object: The object's name.
        link: The hand link.
        geometry: The hand collision geometry.
        position: The object's position in the hand base frame [m], (3,) list.
        q: The hand configuration (URDF coordinates [rad or m]), list.
        detail: What is wrong with the pair.
    """

    def __init__(
        self,
        object_name: str,
        link: str,
        geometry: str,
        position: Iterable[float],
        q: Iterable[float],
        detail: str,
    ) -> None:
        self.object = str(object_name)
        self.link = str(link)
        self.geometry = str(geometry)
        self.position = [float(v) for v in position]
        self.q = [float(v) for v in q]
        self.detail = detail
        where = ", ".join(f"{v * 1e3:.3g}" for v in self.position)
        super().__init__(
            f"contact detection between object {self.object!r} at ({where}) mm and hand link "
            f"{self.link!r} (geometry {self.geometry!r}) at q = {[round(v, 6) for v in self.q]}: "
            f"{detail}; move the object or the hand, or load a mesh object with convex=True "
            "(docs/hands.md, mesh objects)"
        )

    def __reduce__(self) -> tuple:  # picklable (batch workers) with its attributes
        return (type(self), (self.object, self.link, self.geometry, self.position, self.q, self.detail))
