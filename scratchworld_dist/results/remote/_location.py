"""Where a remote run directory is: an fsspec URL parsed, checked for credentials and opened as a filesystem.

Credentials come from the environment (``AWS_*`` for S3, the SDK's usual chain); a URL that carries them
(``s3://key:secret@bucket``) is refused, because the URL is recorded in manifests, logs and error lines. fsspec
and its protocol packages (s3fs, gcsfs, adlfs) are imported only when a remote run is opened.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import TYPE_CHECKING
from urllib.parse import urlsplit

from scratchworld_dist._errors import RunDirError

if TYPE_CHECKING:
    from fsspec import AbstractFileSystem

_URL = re.compile(r"^([a-z][a-z0-9+.-]*)://", re.IGNORECASE)
_PACKAGES = {"s3": "s3fs", "s3a": "s3fs", "gs": "gcsfs", "gcs": "gcsfs", "az": "adlfs", "abfs": "adlfs"}


def is_remote(text: str | object) -> bool:
    """Whether ``text`` names a remote location (``scheme://...``) rather than a local path."""
    return isinstance(text, str) and _URL.match(text) is not None


def redact(text: str) -> str:
    """``text`` with any ``user:password@`` part of a URL in it replaced (for error lines)."""
    return re.sub(r"(://)[^/@\s]*@", r"\1***@", text)


@dataclass(frozen=True)
class RemoteLocation:
    """A run directory's URL: ``protocol://root`` (no trailing slash)."""

    protocol: str
    root: str
    """The path fsspec names it by: ``bucket/prefix`` for object stores, an absolute path for ``file://``."""

    @property
    def url(self) -> str:
        return f"{self.protocol}://{self.root}"

    def key(self, relative: str) -> str:
        """The fsspec path of a file of the run (``relative`` as in the local layout: ``jobs/part-000001.parquet``)."""
        return f"{self.root}/{relative}"

    def filesystem(self) -> AbstractFileSystem:
        """The location's fsspec filesystem (configured by the environment: ``AWS_ENDPOINT_URL``, ``FSSPEC_S3_*``)."""
        try:
            import fsspec
        except ImportError:
            need = "remote run directories need fsspec: pip install 'scratchworld-dist[s3]'"
            raise RunDirError(f"{self.url}: {need}") from None
        try:
            return fsspec.filesystem(self.protocol, skip_instance_cache=True)
        except ImportError:
            package = _PACKAGES.get(self.protocol, f"the fsspec package for {self.protocol}://")
            need = f"{self.protocol}:// run directories need {package}: pip install {package}"
            raise RunDirError(f"{self.url}: {need}") from None
        except ValueError as exc:
            raise RunDirError(f"{self.url}: {exc}") from None


def parse_location(text: str) -> RemoteLocation:
    """The location ``text`` names; ``RunDirError`` (with the credentials redacted) for a URL that carries any,
    names no bucket, or is not a URL."""
    match = _URL.match(text)
    if match is None:
        raise RunDirError(f"{text}: not a URL (expected scheme://bucket/prefix, e.g. s3://lab-results/sweeps/demo)")
    protocol = match.group(1).lower()
    parts = urlsplit(text)
    if "@" in parts.netloc:
        raise RunDirError(
            f"{redact(text)}: credentials in a URL are refused (they would reach manifests and logs); "
            "give them in the environment (AWS_ACCESS_KEY_ID, AWS_SECRET_ACCESS_KEY, or a profile)"
        )
    if parts.query or parts.fragment:
        raise RunDirError(f"{text}: a run directory's URL takes no ?query or #fragment")
    root = text[match.end() :].rstrip("/")
    if protocol == "file":
        root = "/" + root.lstrip("/")
    elif not root or root.startswith("/"):
        raise RunDirError(f"{text}: names no bucket (expected {protocol}://bucket/prefix)")
    return RemoteLocation(protocol=protocol, root=root)
