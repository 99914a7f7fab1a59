"""What changed between two rosters, in sentences a teacher can check.

Works on `to_dict()` output (or the JSON written by `roster links --format
json`), so a roster can be compared with the version published last week
without keeping the old input files. A group whose members are mostly the same
under a new name is reported as renamed, not as every member moving.
"""

from __future__ import annotations

from typing import Any


def _marks(data: dict[str, Any]) -> dict[str, str]:
    """id -> its marks as written (`X`), for members that carry any."""
    out: dict[str, str] = {}
    for group in data.get("groups", []):
        for member in group.get("members", []):
            marks = member.get("marks") or []
            if isinstance(marks, list) and marks:
                out.setdefault(str(member.get("id", "")), " ".join(str(m) for m in marks))
    return out


def _members(
    data: dict[str, Any],
) -> tuple[dict[str, str], dict[str, str], dict[str, str], dict[str, set[str]]]:
    """(id -> group name, id -> account, group -> leader, group -> member ids)."""
    group_of: dict[str, str] = {}
    account_of: dict[str, str] = {}
    leader_of: dict[str, str] = {}
    ids_of: dict[str, set[str]] = {}
    for group in data.get("groups", []):
        name = str(group.get("name", ""))
        leader_of[name] = str(group.get("leader", ""))
        ids = ids_of.setdefault(name, set())
        for member in group.get("members", []):
            sid = str(member.get("id", ""))
            ids.add(sid)
            group_of.setdefault(sid, name)
            account_of.setdefault(sid, str(member.get("account", sid)))
    return group_of, account_of, leader_of, ids_of


def _renames(old_ids: dict[str, set[str]], new_ids: dict[str, set[str]]) -> dict[str, str]:
    """Old group name -> new name, for groups that vanished while a group of mostly the same
    members appeared."""
    removed = [g for g in old_ids if g not in new_ids]
    added = [g for g in new_ids if g not in old_ids]
    renames: dict[str, str] = {}
    for old in removed:
        best, best_overlap = None, 0
        for new in added:
            if new in renames.values():
                continue
            overlap = len(old_ids[old] & new_ids[new])
            if overlap > best_overlap:
                best, best_overlap = new, overlap
        if best is not None and best_overlap * 2 > max(len(old_ids[old]), len(new_ids[best])):
            renames[old] = best
    return renames


def diff(old: dict[str, Any], new: dict[str, Any]) -> list[str]:
    """Human-readable changes from `old` to `new` (both `to_dict()` shaped), in a stable order.

    Lines: groups added/removed/renamed, leaders changed, members added, removed
    or moved between groups, accounts changed, marks set or cleared. Empty list: no change.
    """
    old_group, old_account, old_leader, old_ids = _members(old)
    new_group, new_account, new_leader, new_ids = _members(new)
    renames = _renames(old_ids, new_ids)
    lines: list[str] = []
    for name, new_name in renames.items():
        lines.append(f"group renamed: {name} -> {new_name}")
    for name in old_ids:
        if name not in new_ids and name not in renames:
            lines.append(f"group removed: {name} ({len(old_ids[name])} members)")
    for name in new_ids:
        if name not in old_ids and name not in renames.values():
            lines.append(f"group added: {name} ({len(new_ids[name])} members)")
    for name, leader in old_leader.items():
        target = renames.get(name, name)
        if target in new_leader and new_leader[target] != leader:
            lines.append(f"leader changed in {target}: {leader} -> {new_leader[target]}")
    for sid in sorted(set(old_group) | set(new_group)):
        if sid not in new_group:
            lines.append(f"member removed: {sid} (was in {old_group[sid]})")
        elif sid not in old_group:
            lines.append(f"member added: {sid} ({new_account[sid]}) in {new_group[sid]}")
        else:
            before = renames.get(old_group[sid], old_group[sid])
            if before != new_group[sid]:
                lines.append(f"member moved: {sid} from {old_group[sid]} to {new_group[sid]}")
            if old_account[sid] != new_account[sid]:
                lines.append(f"account changed: {sid}: {old_account[sid]} -> {new_account[sid]}")
    old_marks, new_marks = _marks(old), _marks(new)
    for sid in sorted(set(old_marks) | set(new_marks)):
        before, after = old_marks.get(sid), new_marks.get(sid)
        if before == after:
            continue
        if before is None:
            lines.append(f"member marked: {sid} {after} (in {new_group.get(sid, '?')})")
        elif after is None:
            if sid in new_group:
                lines.append(f"mark removed: {sid} (was {before})")
        else:
            lines.append(f"mark changed: {sid}: {before} -> {after}")
    return lines
