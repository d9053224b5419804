"""Which files on disk may be executed or unpickled: the trust rule of shared caches.

A file is only as safe as the folders above it: whoever can write a folder can replace what is
in it. So a path is *trusted* when every component from a root down to it, looked at with
``lstat`` (links are never followed), is a real folder or regular file

- owned by this user, by root, or by an owner named in ``$STABILITY_CACHE_OWNER`` (user names
  or ids, comma-separated: the account that prepared a shared cache), and
- writable by nobody else: neither by others nor by its group, unless its group is the one named
  in ``$STABILITY_CACHE_GROUP`` (a documented opt-in: that group's members are then trusted as
  writers, and any file of that group is trusted as theirs).

A file is then read through one descriptor, opened without following a link and without
blocking (a FIFO in its place is refused, not waited on), checked with ``fstat`` (a regular file
of a trusted owner, not writable by others, with one link) and read from that same descriptor,
so the bytes checked are the bytes used. A private folder (:func:`private_folder_problem`) is
held to more: owned by this user and closed to group and others (mode ``0o077`` clear).
"""

from __future__ import annotations

import errno
import grp
import os
import pwd
import stat
from dataclasses import dataclass
from pathlib import Path

#: Environment variable naming the owners of a shared cache to trust beside this user and root.
OWNER_ENV = "STABILITY_CACHE_OWNER"
#: Environment variable naming the group whose members may write a shared cache.
GROUP_ENV = "STABILITY_CACHE_GROUP"

_NOFOLLOW = getattr(os, "O_NOFOLLOW", 0)
_NONBLOCK = getattr(os, "O_NONBLOCK", 0)
_CLOEXEC = getattr(os, "O_CLOEXEC", 0)


class UntrustedPath(OSError):
    """A path that fails the trust rule; its message says which component and why."""


@dataclass(frozen=True)
class TrustRule:
    """Who may have written a file that is executed or unpickled: owners and a writers' group."""

    owners: frozenset[int]
    group: int | None = None

    @classmethod
    def from_environment(cls, environ=os.environ) -> TrustRule:
        """This user and root, the owners of ``$STABILITY_CACHE_OWNER`` and the group of
        ``$STABILITY_CACHE_GROUP``; a name that is no user or group is ignored (it trusts no
        one more)."""
        owners = {os.getuid(), 0}
        for name in filter(None, (n.strip() for n in environ.get(OWNER_ENV, "").split(","))):
            uid = _lookup(name, pwd.getpwnam, "pw_uid")
            if uid is not None:
                owners.add(uid)
        name = environ.get(GROUP_ENV, "").strip()
        group = _lookup(name, grp.getgrnam, "gr_gid") if name else None
        return cls(frozenset(owners), group)

    @classmethod
    def private(cls) -> TrustRule:
        """This user alone (and root, who can write anything anyway)."""
        return cls(frozenset({os.getuid(), 0}))

    def problem(self, st: os.stat_result) -> str | None:
        """Why a file or folder of status ``st`` (``lstat``'s or ``fstat``'s) is not trusted,
        or None; a regular file must also have one name (no hard link to it elsewhere)."""
        mode = st.st_mode
        if stat.S_ISLNK(mode):
            return "is a symbolic link"
        if not (stat.S_ISDIR(mode) or stat.S_ISREG(mode)):
            return "is neither a folder nor a regular file"
        by_group = self.group is not None and st.st_gid == self.group
        if st.st_uid not in self.owners and not by_group:
            return f"belongs to {_user(st.st_uid)}, whom this user does not trust"
        if mode & stat.S_IWOTH and not (stat.S_ISDIR(mode) and mode & stat.S_ISVTX
                                        and st.st_uid in self.owners):
            return "is writable by every user"
        if mode & stat.S_IWGRP and not by_group:
            return f"is writable by its group {_group(st.st_gid)}"
        if stat.S_ISREG(mode) and st.st_nlink != 1:  # a second name of a file elsewhere
            return f"has {st.st_nlink} hard links"
        return None


def chain_problem(root: Path, path: Path, rule: TrustRule) -> str | None:
    """Why ``path`` (``root`` or below it) is not trusted, naming the component, or None.

    Every component from ``root`` down to ``path`` is looked at with ``lstat``; a missing one
    ends the walk (nothing there to trust yet: whoever creates it is this process). ``root``
    itself should be resolved (``os.path.realpath``) by the caller, which chose it.
    """
    parts = path.relative_to(root).parts
    current = root
    for part in ("", *parts):
        current = current / part if part else current
        try:
            st = os.lstat(current)
        except FileNotFoundError:
            return None
        except OSError as exc:
            return f"{current} cannot be examined ({exc.strerror or exc})"
        why = rule.problem(st)
        if why is None and current != path and not stat.S_ISDIR(st.st_mode):
            why = "is not a folder"
        if why is not None:
            return f"{current} {why}"
    return None


def read_trusted(path: Path, rule: TrustRule) -> bytes:
    """The bytes of the regular file ``path``, checked and read through one descriptor.

    Raises FileNotFoundError if it is missing, :class:`UntrustedPath` if it is a link, a FIFO
    or another special file, has more than one link, or fails ``rule``. Only the file is
    checked: its folders are :func:`chain_problem`'s.
    """
    try:
        fd = os.open(path, os.O_RDONLY | _NOFOLLOW | _NONBLOCK | _CLOEXEC)
    except OSError as exc:
        if exc.errno == errno.ELOOP:  # O_NOFOLLOW met a link
            raise UntrustedPath(f"{path} is a symbolic link") from None
        raise
    try:
        why = rule.problem(os.fstat(fd))
        if why is not None:
            raise UntrustedPath(f"{path} {why}")
        chunks = []
        while chunk := os.read(fd, 1 << 20):
            chunks.append(chunk)
        return b"".join(chunks)
    finally:
        os.close(fd)


def private_folder_problem(folder: Path) -> str | None:
    """Why ``folder`` is no private folder of this user's, or None: it must be a real folder
    (not a link), owned by this user, with no access for group or others."""
    try:
        st = os.lstat(folder)
    except OSError as exc:
        return f"{folder} cannot be examined ({exc.strerror or exc})"
    if stat.S_ISLNK(st.st_mode):
        return f"{folder} is a symbolic link"
    if not stat.S_ISDIR(st.st_mode):
        return f"{folder} is not a folder"
    if st.st_uid != os.getuid():
        return f"{folder} belongs to {_user(st.st_uid)}"
    if st.st_mode & 0o077:
        return f"{folder} is open to other users (mode {st.st_mode & 0o777:04o})"
    return None


def open_flags() -> int:
    """``os.open`` flags for a file that must not be a link nor block (a FIFO in its place)."""
    return _NOFOLLOW | _NONBLOCK | _CLOEXEC


def _lookup(name: str, by_name, field: str) -> int | None:
    if name.isdigit():
        return int(name)
    try:
        return getattr(by_name(name), field)
    except KeyError:
        return None


def _user(uid: int) -> str:
    try:
        return f"user {pwd.getpwuid(uid).pw_name}"
    except KeyError:
        return f"user id {uid}"


def _group(gid: int) -> str:
    try:
        return grp.getgrgid(gid).gr_name
    except KeyError:
        return str(gid)


__all__ = ["GROUP_ENV", "OWNER_ENV", "TrustRule", "UntrustedPath", "chain_problem",
           "open_flags", "private_folder_problem", "read_trusted"]
