"""The module-wide S3 server (moto's, on 127.0.0.1) the object-storage tests write to and read from."""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from tests.support.s3_server import S3Server, s3_server_fixture


@pytest.fixture(scope="module")
def s3(tmp_path_factory: pytest.TempPathFactory) -> Iterator[S3Server]:
    yield from s3_server_fixture(tmp_path_factory)
