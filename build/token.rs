//! The FMI 2.0 `guid` and the FMI 3.0 `instantiationToken`, derived from the model description's
//! own text, so that two FMUs share a token only when they declare the same interface.
//!
//! The hand-kept descriptions carry [`PLACEHOLDER`] as the value of the attribute; the build
//! replaces it with the token of the text ([`derive`]) and ships the result ([`with_token`]). The
//! token is SHA-256 of the *normalised* text, in which the attribute still holds the placeholder,
//! written as an RFC 9562 version-8 UUID (the first 128 bits of the digest with the version and
//! variant bits set), in braces as FMI tools write GUIDs. Normalising removes what a checkout can
//! change without changing the file: a UTF-8 byte-order mark and the line ends (CRLF or CR, as a
//! Windows checkout with `core.autocrlf` writes them, become LF). Everything else counts, comments
//! included: a new token for an unchanged interface only makes importers reload the FMU, while one
//! token for two interfaces would let a cache or a host mix them up.
//!
//! Shared by `build.rs` and the test `tests/model_description_token.rs`.

use sha2::{Digest, Sha256};

/// The value of the token attribute in the hand-kept model descriptions.
pub const PLACEHOLDER: &str = "{derived-at-build-time}";

/// The text with a byte-order mark removed and every line end as LF.
pub fn normalise(xml: &str) -> String {
    xml.strip_prefix('\u{feff}')
        .unwrap_or(xml)
        .replace("\r\n", "\n")
        .replace('\r', "\n")
}

/// `attribute="PLACEHOLDER"` as it must occur in the text.
fn placeholder_attribute(attribute: &str) -> String {
    format!("{attribute}=\"{PLACEHOLDER}\"")
}

/// Checks that `attribute` occurs once and holds [`PLACEHOLDER`] in `xml`.
fn check_placeholder(xml: &str, attribute: &str) -> Result<(), String> {
    let declared = xml.matches(&format!("{attribute}=\"")).count();
    let placeholders = xml.matches(&placeholder_attribute(attribute)).count();
    if declared == 1 && placeholders == 1 {
        Ok(())
    } else {
        Err(format!(
            "{attribute} must be declared once, as {attribute}=\"{PLACEHOLDER}\": the build derives \
             it from the file's content (found {declared} declarations, {placeholders} with the \
             placeholder)"
        ))
    }
}

/// The token of a model description whose `attribute` (`guid` or `instantiationToken`) holds
/// [`PLACEHOLDER`]: SHA-256 of the normalised text as a version-8 UUID in braces.
pub fn derive(xml: &str, attribute: &str) -> Result<String, String> {
    let text = normalise(xml);
    check_placeholder(&text, attribute)?;
    let digest = Sha256::digest(text.as_bytes());
    let mut bytes = [0u8; 16];
    bytes.copy_from_slice(&digest[..16]);
    bytes[6] = (bytes[6] & 0x0f) | 0x80; // version 8: custom (RFC 9562 §5.8)
    bytes[8] = (bytes[8] & 0x3f) | 0x80; // variant 10: RFC 9562
    let hex: String = bytes.iter().map(|b| format!("{b:02x}")).collect();
    Ok(format!(
        "{{{}-{}-{}-{}-{}}}",
        &hex[0..8],
        &hex[8..12],
        &hex[12..16],
        &hex[16..20],
        &hex[20..32]
    ))
}

/// The model description as the FMU ships it: normalised, with `token` in place of the
/// placeholder.
pub fn with_token(xml: &str, attribute: &str, token: &str) -> Result<String, String> {
    let text = normalise(xml);
    check_placeholder(&text, attribute)?;
    Ok(text.replacen(
        &placeholder_attribute(attribute),
        &format!("{attribute}=\"{token}\""),
        1,
    ))
}
