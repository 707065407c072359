"""Serialized FMU states as JSON, for tests that craft states: `decode` gives the payload of the
bytes fmi2SerializeFMUstate wrote (after checking the framing), `encode` frames a payload again
with a fresh checksum, so that a test can change one field and see what fmi2DeSerializeFMUstate /
fmi2SetFMUstate make of it. The layout is the one of src/fmi/serialized.rs (docs/fmu.md)."""

import json
import struct
import zlib

MAGIC = b"PLIMPST\0"
FORMAT_VERSION = 5


def decode(data):
    """The payload (a JSON tree) and the crate version of serialized state bytes."""
    data = bytes(data)
    assert data[:8] == MAGIC, "not a PlateImpact FMU state"
    (version,) = struct.unpack_from("<I", data, 8)
    assert version == FORMAT_VERSION, version
    (n,) = struct.unpack_from("<H", data, 12)
    crate_version = data[14 : 14 + n]
    (m,) = struct.unpack_from("<Q", data, 14 + n)
    start = 22 + n
    payload = data[start : start + m]
    (checksum,) = struct.unpack_from("<I", data, start + m)
    assert checksum == zlib.crc32(data[: start + m]), "checksum mismatch"
    assert len(data) == start + m + 4, "trailing bytes"
    return json.loads(payload), crate_version


def encode(payload, crate_version):
    """Serialized state bytes around `payload` (a JSON tree, or JSON text) with a fresh checksum."""
    text = payload if isinstance(payload, str) else json.dumps(payload)
    body = (
        MAGIC
        + struct.pack("<I", FORMAT_VERSION)
        + struct.pack("<H", len(crate_version))
        + crate_version
        + struct.pack("<Q", len(text.encode()))
        + text.encode()
    )
    return body + struct.pack("<I", zlib.crc32(body))
