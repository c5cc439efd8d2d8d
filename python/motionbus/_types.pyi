from typing import Union

BytesLike = Union[bytes, bytearray, memoryview]
