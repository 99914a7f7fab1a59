"""YAML rosters: `groups: [{name, members: [{id, account, notes?}], leader?}]`.

For rosters kept by hand in a repository, where comments and an explicit leader
are welcome. Values are read as text with their line numbers (see yamlnodes),
so `id: 040823131` keeps its leading zero and errors point at the right line.
"""

from __future__ import annotations

import yaml

from .records import Collector, RawGroup, describe_members, make_member
from .yamlnodes import ROOT, Node, Walker, compose, describe, line_of

GROUP_KEYS = {"name", "members", "leader"}
MEMBER_KEYS = {"id", "account", "notes"}


def parse_yaml(lines: list[str], c: Collector) -> list[RawGroup]:
    """Parse a YAML roster into raw groups, reporting into `c`."""
    before = len(c.diagnostics)
    root = compose("\n".join(lines), c)
    if root is None:
        if len(c.diagnostics) == before:
            c.error(1, "file", "empty file: expected a mapping with a 'groups' list")
        return []
    w = Walker(c)
    groups_node = None
    for key, key_node, value in w.mapping(root, ROOT):
        if key == "groups":
            groups_node = value
        else:
            c.error(line_of(key_node), key, f"unknown key {key!r} (expected 'groups')")
    if groups_node is None:
        c.error(line_of(root), "groups", "missing 'groups' list")
        return []
    groups = []
    for gi, group_node in enumerate(w.sequence(groups_node, "groups"), 1):
        group = _group(w, group_node, gi)
        if group is not None:
            groups.append(group)
    return groups


def _group(w: Walker, node: Node, gi: int) -> RawGroup | None:
    c = w.c
    name = leader = None
    members_node = None
    leader_line = 0
    for key, key_node, value in w.mapping(node, f"group {gi}"):
        if key == "name":
            name = w.text(value, "group name")
        elif key == "leader":
            leader = w.text(value, "group leader")
            leader_line = line_of(value)
        elif key == "members":
            members_node = value
        else:
            c.error(
                line_of(key_node),
                f"group {gi}",
                f"unknown key {key!r} (expected one of {sorted(GROUP_KEYS)})",
            )
    group = RawGroup(name=name or "", line=line_of(node), field="group name")
    if leader is not None:
        group.leader, group.leader_line, group.leader_field, group.leader_file = (
            leader,
            leader_line,
            "group leader",
            c.file,
        )
    if members_node is not None:
        for mi, member_node in enumerate(w.sequence(members_node, "members"), 1):
            _member(w, member_node, mi, group)
    if name is None:
        ids = describe_members(group.members)
        c.error(line_of(node), "group name", f"group {gi} has no name (members: {ids})")
        return None
    return group


def _member(w: Walker, node: Node, mi: int, group: RawGroup) -> None:
    c = w.c
    where = f"member {mi}"
    if not isinstance(node, yaml.MappingNode):
        c.error(
            line_of(node),
            where,
            f"member must be a mapping with id and account, got {describe(node)}",
        )
        return
    sid = account = None
    notes: list[str] = []
    id_line = account_line = line_of(node)
    for key, key_node, value in w.mapping(node, where):
        if key == "id":
            sid = w.text(value, f"{where} id", allow_empty=True)
            id_line = line_of(value)
        elif key == "account":
            account = w.text(value, f"{where} account", allow_empty=True)
            account_line = line_of(value)
        elif key == "notes":
            if isinstance(value, yaml.ScalarNode):
                text = w.text(value, f"{where} notes", allow_empty=True)
                notes += [text] if text else []
            else:
                for item in w.sequence(value, f"{where} notes"):
                    text = w.text(item, f"{where} notes")
                    notes += [text] if text else []
        else:
            c.error(
                line_of(key_node),
                where,
                f"unknown key {key!r} (expected one of {sorted(MEMBER_KEYS)})",
            )
    if not sid:
        c.error(id_line, f"{where} id", f"member has no id (account {account or 'none'})")
        return
    member = make_member(
        c,
        sid,
        account,
        id_line,
        f"{where} id",
        f"{where} account",
        missing_account="no account given" if account is None else "empty account",
    )
    if member is None:
        return
    if account_line != id_line:
        member.account_field = f"{where} account (line {account_line})"
    member.notes += tuple(notes)
    group.members.append(member)
