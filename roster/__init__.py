"""Course rosters: parse, correct, validate and link student groups.

    from roster import load_roster, RosterError, Diagnostic, diff
    result = load_roster("stage3_2a.txt", corrections="stage3_2a.corrections.yml")
    if result.errors: ...
    data = result.to_dict()

Independent of `sitegen` (which imports this package, never the reverse).
"""

from .diff import diff
from .load import load_roster
from .model import Diagnostic, Group, Member, Roster, RosterError, RosterResult

__all__ = [
    "Diagnostic",
    "Group",
    "Member",
    "Roster",
    "RosterError",
    "RosterResult",
    "diff",
    "load_roster",
]
