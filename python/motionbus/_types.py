"""Type aliases of the package's arguments."""

from typing import Union

BytesLike = Union[bytes, bytearray, memoryview]
