"""Exceptions of the motions room: a motion file or model that cannot be read, written or converted.

Every error says where: the file (``path``), the 1-based ``line`` and the ``field`` (attribute, element,
column or joint name), so a user can open the file at the right place without re-running anything.
"""

from __future__ import annotations

from kinematics.errors import ToolkitError


class MotionFormatError(ToolkitError, ValueError):
    """A motion file or motion model that breaks its format's rules.

    The message reads ``walk.xml:12: field 'end' of <lle3>: expected a number, got 'abc'``; parts that are
    unknown (a model built in code has no path or line) are left out.

    Args:
        detail: what is wrong, with the expected and the actual value.
        path: the file (as the caller named it), ``"<string>"`` for text given directly, None if unknown.
        line: 1-based line number in that file, None if unknown.
        field: the attribute, element, column or joint that is wrong (e.g. ``"end"``, ``"firstPhase"``,
            ``"RShoulderPitch"``, ``"time"``), None for whole-file problems (not well-formed XML).
        element: the XML element or Webots pose the field belongs to (``"lle3"``, ``"phase 'walk1'"``),
            only used to make the message readable.
    """

    def __init__(self, detail: str, *, path: str | None = None, line: int | None = None,
                 field: str | None = None, element: str | None = None) -> None:
        self.detail = detail
        self.path = path
        self.line = line
        self.field = field
        self.element = element
        super().__init__(self._compose())

    def __reduce__(self) -> tuple[object, ...]:
        # Keyword-only arguments: rebuild through a helper so the error survives pickling (process pools).
        return (_rebuild, (type(self), self.detail, self.path, self.line, self.field, self.element))

    def _compose(self) -> str:
        where = ""
        if self.path is not None:
            where = self.path if self.line is None else f"{self.path}:{self.line}"
        elif self.line is not None:
            where = f"line {self.line}"
        what = ""
        if self.field is not None:
            what = f"field '{self.field}'"
            if self.element is not None:
                what += f" of <{self.element}>" if not self.element.startswith(("phase ", "pose ")) \
                    else f" of {self.element}"
        parts = [p for p in (where, what, self.detail) if p]
        return ": ".join(parts)


class ConversionError(MotionFormatError):
    """A motion that the target format cannot express (flags, cycles or computed values in a Webots file,
    a duration that is not a whole number of milliseconds, ...). The message names the option, if any,
    that allows the lossy conversion."""


def _rebuild(cls: type[MotionFormatError], detail: str, path: str | None, line: int | None, field: str | None,
             element: str | None) -> MotionFormatError:
    return cls(detail, path=path, line=line, field=field, element=element)
