//! The byte format of a serialized FMU state (fmi2SerializeFMUstate / fmi2DeSerializeFMUstate).
//!
//! Layout, all integers little-endian:
//!
//! | bytes | content |
//! |---|---|
//! | 8 | magic `PLIMPST\0` |
//! | 4 | format version ([`FORMAT_VERSION`]) |
//! | 2 + n | length and UTF-8 text of the crate version that wrote it |
//! | 8 + m | length and the payload: the state as JSON (serde_json, `float_roundtrip`) |
//! | 4 | CRC-32 (IEEE 802.3, as zlib's `crc32`) of everything before it |
//!
//! Decoding checks every field and returns an error naming the first that does not match; it never
//! trusts a length before checking it against the bytes at hand. The checksum detects corruption
//! only: a buffer with a matching checksum may still be foreign or crafted, so the FMU validates
//! every decoded field as untrusted input afterwards. JSON keeps the payload readable for
//! debugging (and lets tests craft payloads: [`decode_json`], [`encode_payload`]), and with
//! serde_json's `float_roundtrip` feature every finite f64 reads back bit-identically (ryu writes
//! the shortest text that parses to the same bits, and the feature makes the parser exact).

use serde::de::DeserializeOwned;
use serde::Serialize;

/// First bytes of every serialized state.
pub const MAGIC: [u8; 8] = *b"PLIMPST\0";
/// Version of this layout and of the payload's structure; bump when either changes.
pub const FORMAT_VERSION: u32 = 5;
/// The crate version written into (and required from) a serialized state.
pub const CRATE_VERSION: &str = env!("CARGO_PKG_VERSION");

/// Encodes `value` in the layout above.
pub fn encode<T: Serialize>(value: &T) -> Result<Vec<u8>, String> {
    let payload =
        serde_json::to_vec(value).map_err(|e| format!("cannot serialize the FMU state: {e}"))?;
    Ok(encode_payload(&payload))
}

/// The bytes of the layout around a payload given as JSON text, with a fresh checksum. [`encode`]
/// uses it; tests use it to craft states: a buffer that passes every framing check and carries
/// whatever payload the test wants.
pub fn encode_payload(payload: &[u8]) -> Vec<u8> {
    let mut out = Vec::with_capacity(payload.len() + 48);
    out.extend_from_slice(&MAGIC);
    out.extend_from_slice(&FORMAT_VERSION.to_le_bytes());
    out.extend_from_slice(&(CRATE_VERSION.len() as u16).to_le_bytes());
    out.extend_from_slice(CRATE_VERSION.as_bytes());
    out.extend_from_slice(&(payload.len() as u64).to_le_bytes());
    out.extend_from_slice(payload);
    let sum = crc32fast::hash(&out);
    out.extend_from_slice(&sum.to_le_bytes());
    out
}

/// A cursor that refuses to read past the end.
struct Reader<'a> {
    bytes: &'a [u8],
    at: usize,
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize, what: &str) -> Result<&'a [u8], String> {
        let end = self
            .at
            .checked_add(n)
            .filter(|&e| e <= self.bytes.len())
            .ok_or_else(|| {
                format!(
                    "serialized FMU state is truncated: {what} needs {n} bytes at offset {}, only {} left",
                    self.at,
                    self.bytes.len().saturating_sub(self.at)
                )
            })?;
        let s = &self.bytes[self.at..end];
        self.at = end;
        Ok(s)
    }
}

/// Decodes bytes written by [`encode`], checking magic, versions, lengths and checksum.
pub fn decode<T: DeserializeOwned>(bytes: &[u8]) -> Result<T, String> {
    serde_json::from_slice(payload(bytes)?)
        .map_err(|e| format!("serialized FMU state has an invalid payload: {e}"))
}

/// The payload of a serialized state as a JSON tree (for inspecting or crafting states in tests).
pub fn decode_json(bytes: &[u8]) -> Result<serde_json::Value, String> {
    decode(bytes)
}

/// The payload of a serialized state, after every framing check.
fn payload(bytes: &[u8]) -> Result<&[u8], String> {
    let mut r = Reader { bytes, at: 0 };
    if r.take(8, "the magic number")? != MAGIC {
        return Err(
            "serialized FMU state: not a PlateImpact FMU state (wrong magic number)".into(),
        );
    }
    let version = u32::from_le_bytes(r.take(4, "the format version")?.try_into().unwrap());
    if version != FORMAT_VERSION {
        return Err(format!(
            "serialized FMU state has format version {version}, this FMU reads version {FORMAT_VERSION}"
        ));
    }
    let n = u16::from_le_bytes(r.take(2, "the crate version length")?.try_into().unwrap());
    let crate_version = r.take(n as usize, "the crate version")?;
    if crate_version != CRATE_VERSION.as_bytes() {
        return Err(format!(
            "serialized FMU state was written by PlateImpact {:?}, this is {CRATE_VERSION}",
            String::from_utf8_lossy(crate_version)
        ));
    }
    let m = u64::from_le_bytes(r.take(8, "the payload length")?.try_into().unwrap());
    let m = usize::try_from(m).map_err(|_| "serialized FMU state: payload length overflows")?;
    let payload = r.take(m, "the payload")?;
    let body_end = r.at;
    let sum = u32::from_le_bytes(r.take(4, "the checksum")?.try_into().unwrap());
    if r.at != bytes.len() {
        return Err(format!(
            "serialized FMU state has {} trailing bytes",
            bytes.len() - r.at
        ));
    }
    if crc32fast::hash(&bytes[..body_end]) != sum {
        return Err("serialized FMU state is corrupt (checksum mismatch)".into());
    }
    Ok(payload)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn floats_round_trip_bit_exactly() {
        let mut values: Vec<f64> = vec![0.1, 1.0 / 3.0, -0.0, 5e-324, f64::MAX, f64::MIN_POSITIVE];
        let mut x: u64 = 0x1234_5678_9abc_def0;
        for _ in 0..2000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            let v = f64::from_bits(x);
            if v.is_finite() {
                values.push(v);
            }
        }
        let back: Vec<f64> = decode(&encode(&values).unwrap()).unwrap();
        for (a, b) in values.iter().zip(&back) {
            assert_eq!(a.to_bits(), b.to_bits());
        }
    }

    #[test]
    fn every_corruption_is_an_error() {
        let bytes = encode(&vec![1.0f64, 2.0, 3.0]).unwrap();
        for i in 0..bytes.len() {
            let mut bad = bytes.clone();
            bad[i] ^= 0x40;
            assert!(
                decode::<Vec<f64>>(&bad).is_err(),
                "flip at byte {i} accepted"
            );
        }
        for n in 0..bytes.len() {
            assert!(
                decode::<Vec<f64>>(&bytes[..n]).is_err(),
                "truncation to {n} accepted"
            );
        }
        let mut longer = bytes.clone();
        longer.push(0);
        assert!(decode::<Vec<f64>>(&longer).is_err());
        assert!(decode::<Vec<f64>>(&[]).is_err());
    }

    #[test]
    fn crafted_payloads_pass_the_framing_checks() {
        let bytes = encode(&vec![1.0f64, 2.0]).unwrap();
        let mut tree = decode_json(&bytes).unwrap();
        tree[1] = serde_json::json!(-1e308);
        let crafted = encode_payload(&serde_json::to_vec(&tree).unwrap());
        assert_eq!(decode::<Vec<f64>>(&crafted).unwrap(), [1.0, -1e308]);
        // The checksum is zlib's CRC-32, so Python can craft states too.
        assert_eq!(crc32fast::hash(b"123456789"), 0xcbf4_3926);
    }
}
