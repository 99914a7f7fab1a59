"""Group and member repository and site links, and the safety rules for anything in a URL.

Accounts and slugs come from a hand-edited file and end up in `href` attributes
and host names, so they are checked against a deliberately small character set
before any link is built: `javascript:alert(1)` or `../x` must never become a
link. GitHub's own (stricter) username rules are only a warning, because a
roster may legitimately hold an account GitHub would reject today (old accounts,
typos being fixed) and refusing the whole site for that helps nobody.
"""

from __future__ import annotations

import re

SAFE_RE = re.compile(r"[A-Za-z0-9][A-Za-z0-9_.-]*")
SAFE_MAX_LEN = 100  # GitHub repository names are at most 100 characters
GITHUB_USER_RE = re.compile(r"[A-Za-z0-9](?:[A-Za-z0-9]|-(?=[A-Za-z0-9]))*")
GITHUB_USER_MAX_LEN = 39


def is_safe(value: str) -> bool:
    """True if `value` may be placed in a URL path segment or host label as-is."""
    return (
        0 < len(value) <= SAFE_MAX_LEN
        and SAFE_RE.fullmatch(value) is not None
        and ".." not in value
    )


def unsafe_reason(value: str) -> str | None:
    """Why `value` is not URL-safe, or None if it is."""
    if not value:
        return "is empty"
    if len(value) > SAFE_MAX_LEN:
        return f"is longer than {SAFE_MAX_LEN} characters"
    if ".." in value:
        return "contains '..'"
    if SAFE_RE.fullmatch(value) is None:
        bad = next((c for c in value if not (c.isascii() and (c.isalnum() or c in "_.-"))), None)
        if bad is None:
            return "must start with a letter or digit"
        return f"contains {bad!r} (allowed: A-Z a-z 0-9 _ . -, starting with a letter or digit)"
    return None


def github_username_problem(account: str) -> str | None:
    """Why GitHub would reject `account` as a username, or None if it looks valid."""
    if len(account) > GITHUB_USER_MAX_LEN:
        return f"is longer than the {GITHUB_USER_MAX_LEN} characters allowed in a GitHub username"
    if GITHUB_USER_RE.fullmatch(account) is None:
        return (
            "is not a valid GitHub username (letters, digits and single hyphens, "
            "not starting or ending with a hyphen)"
        )
    return None


def repo_url(account: str, repo: str) -> str | None:
    """`https://github.com/{account}/{repo}`, or None if either part is unsafe."""
    if not (is_safe(account) and is_safe(repo)):
        return None
    return f"https://github.com/{account}/{repo}"


def site_url(account: str, repo: str) -> str | None:
    """`https://{account}.github.io/{repo}`, or None if either part is unsafe."""
    if not (is_safe(account) and is_safe(repo)):
        return None
    return f"https://{account}.github.io/{repo}"
