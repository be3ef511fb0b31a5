"""User-facing errors: one type per kind, each message one line naming the culprit.

The command line catches :class:`CrankbookError` once and prints its message.
"""


class CrankbookError(Exception):
    """Base of every error a user can cause by what they ask for."""


class CrankbookWarning(UserWarning):
    """A value that is legal but implausible (grams typed for kg, bar for MPa), or a
    file read as it is though it may mislead (saved without calculated values): one
    line, the work goes on.  The command line prints it as ``crankbook: warning: …``."""


class CoarseStepWarning(CrankbookWarning):
    """A main grid coarser than the peaks need (``step=``/``--step`` above 5°):
    Results.coarse_step_effect measures what it does; the tests, which build coarse
    grids on purpose, silence it."""


class UncalculatedWorkbookWarning(CrankbookWarning):
    """A workbook saved without calculated values (openpyxl writes formulas only), read
    as it is: its q_ values read as NaN.  The commands that read results (``export``)
    recalculate such a file in LibreOffice instead."""


class StaleWorkbookWarning(CrankbookWarning):
    """A workbook whose stored results its own inputs no longer give (an input typed
    with calculation set to manual, or by a script), read as it is.  ``read`` names the
    first such result (``name``, "q_torque"); ``read(recalculate=True)`` and ``export``
    recalculate instead."""

    def __init__(self, message, name=None):
        super().__init__(message)
        self.name = name


class UnknownPresetError(CrankbookError):
    """A preset or workbook template name that does not exist."""


class UnknownGroupError(CrankbookError):
    """A class group number that the preset's group table does not have."""


class UnknownParameterError(CrankbookError):
    """A ``--set`` key that is not a parameter of the workbook."""


class ParameterValueError(CrankbookError):
    """A parameter value that is not a number or breaks its own bounds."""


class GeometryError(CrankbookError):
    """Parameters that are each fine but together describe no mechanism."""


class PressureFileError(CrankbookError):
    """A measured pressure trace that cannot be read or does not cover the cycle."""


class BuildOptionError(CrankbookError):
    """A build option (grid step, output path, language) that cannot be used.

    ``keyword``: the API keyword the message names (``step``, ``cam_step``), which the
    command line shows as its flag (``--step``, ``--cam-step``)."""

    def __init__(self, message, keyword=None):
        super().__init__(message)
        self.keyword = keyword

    def for_command_line(self):
        """The message with the keyword (``step=10``) as the flag (``--step 10``)."""
        text = str(self)
        if self.keyword and text.startswith(f"{self.keyword}="):
            flag = "--" + self.keyword.replace("_", "-")
            text = f"{flag} {text[len(self.keyword) + 1:]}"
        return text


class OutputPathError(BuildOptionError):
    """An output path that cannot be written (no such place, read-only, name too long)."""


class WorkbookReadError(CrankbookError):
    """A file that is not a readable workbook written by this tool."""


class RecalculationError(CrankbookError):
    """LibreOffice is missing or failed to recalculate a workbook."""


class RosterError(CrankbookError):
    """A roster that is missing, malformed, or has empty or duplicate ids."""


class AssignmentDirError(CrankbookError):
    """A directory that `assign` did not write (no manifest), or one it cannot use."""


class SpecError(CrankbookError):
    """A template (spec) file that says something the language cannot mean.

    ``file`` and ``key`` name the file under templates/ and the entry at fault.
    """

    def __init__(self, file, key, message):
        self.file, self.key = file, key
        super().__init__(f"templates/{file}: {key}: {message}")


class LayoutError(CrankbookError):
    """A per-item table (cylinders, stages, gears, …) whose rows do not fit together."""


class BuildCancelled(CrankbookError):
    """A run that cannot go on (e.g. another run is writing into the same place)."""
