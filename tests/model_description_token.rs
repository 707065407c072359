//! The guid / instantiationToken derived from each model description's content (build/token.rs):
//! the same text gives the same token however a checkout wrote its line ends, a changed variable
//! gives another, the library carries the tokens of the shipped descriptions, and a hand-written
//! token is refused.

#[path = "../build/token.rs"]
mod token;

use plate_impact::fmi::variables::{FMI2, FMI3, SHIPPED_FMI2_XML, SHIPPED_FMI3_XML};
use token::{derive, with_token, PLACEHOLDER};

const XML: &str = include_str!("../modelDescription/modelDescription.xml");
const XML3: &str = include_str!("../modelDescription/modelDescription-fmi3.xml");

/// `text` with `from` (which must occur exactly once) replaced by `to`.
fn edited(text: &str, from: &str, to: &str) -> String {
    assert_eq!(text.matches(from).count(), 1, "{from:?} must occur once");
    text.replace(from, to)
}

#[test]
fn a_known_text_gives_the_token_an_independent_sha256_gives() {
    // `printf '<fmiModelDescription fmiVersion="2.0" guid="{derived-at-build-time}"/>\n' |
    // sha256sum` (coreutils) prints 685e881ad561784af65ccd1b029c30b4 94d8...; its first 128 bits
    // with the version nibble 8 (784a -> 884a) and the variant bits 10 (f65c -> b65c) are the token.
    let text = "<fmiModelDescription fmiVersion=\"2.0\" guid=\"{derived-at-build-time}\"/>\n";
    assert_eq!(
        derive(text, "guid").unwrap(),
        "{685e881a-d561-884a-b65c-cd1b029c30b4}"
    );
}

#[test]
fn the_library_carries_the_tokens_of_the_shipped_descriptions() {
    assert_eq!(FMI2.token, derive(XML, "guid").unwrap());
    assert_eq!(FMI3.token, derive(XML3, "instantiationToken").unwrap());
    assert_ne!(FMI2.token, FMI3.token);
    // The FMUs ship the descriptions with the token in place of the placeholder, and nothing else
    // changed.
    for (shipped, source, attribute, token) in [
        (SHIPPED_FMI2_XML, XML, "guid", FMI2.token),
        (SHIPPED_FMI3_XML, XML3, "instantiationToken", FMI3.token),
    ] {
        assert_eq!(shipped.matches(token).count(), 1);
        assert!(!shipped.contains(PLACEHOLDER));
        assert_eq!(shipped.replace(token, PLACEHOLDER), source);
        assert_eq!(with_token(source, attribute, token).unwrap(), shipped);
    }
}

#[test]
fn line_ends_and_a_byte_order_mark_do_not_change_the_token() {
    let token = derive(XML, "guid").unwrap();
    let crlf = XML.replace('\n', "\r\n");
    let cr = XML.replace('\n', "\r");
    let bom = format!("\u{feff}{crlf}");
    for text in [&crlf, &cr, &bom] {
        assert_eq!(derive(text, "guid").unwrap(), token);
        assert_eq!(
            with_token(text, "guid", &token).unwrap(),
            with_token(XML, "guid", &token).unwrap()
        );
    }
}

#[test]
fn a_changed_variable_changes_the_token() {
    let token = derive(XML, "guid").unwrap();
    let changes = [
        // renamed
        edited(
            XML,
            "name=\"corner2.displacement\"",
            "name=\"corner3.displacement\"",
        ),
        // another start value
        edited(
            XML,
            "<Real unit=\"m\" start=\"0.4\"",
            "<Real unit=\"m\" start=\"0.5\"",
        ),
        // another value reference
        edited(XML, "valueReference=\"68\"", "valueReference=\"69\""),
        // the version: a release (X.Y.Z-dev becomes X.Y.Z) has another token than the builds
        // before it
        edited(
            XML,
            &format!("version=\"{}\"", env!("CARGO_PKG_VERSION")),
            "version=\"99.0.0\"",
        ),
    ];
    for changed in &changes {
        assert_ne!(derive(changed, "guid").unwrap(), token);
    }
    let token3 = derive(XML3, "instantiationToken").unwrap();
    let changed3 = edited(
        XML3,
        "name=\"energy.kinetic\"",
        "name=\"energy.kinetic_total\"",
    );
    assert_ne!(derive(&changed3, "instantiationToken").unwrap(), token3);
}

#[test]
fn a_hand_written_or_repeated_token_is_refused() {
    let written = edited(
        XML,
        &format!("guid=\"{PLACEHOLDER}\""),
        "guid=\"{75cd278b-8e21-4b2a-874d-f1cc0adc599e}\"",
    );
    let err = derive(&written, "guid").unwrap_err();
    assert!(err.contains(PLACEHOLDER), "{err}");
    let twice = XML.replacen(
        "modelName=",
        &format!("guid=\"{PLACEHOLDER}\" modelName="),
        1,
    );
    assert!(derive(&twice, "guid")
        .unwrap_err()
        .contains("2 declarations"));
    assert!(derive(XML, "instantiationToken").is_err());
}
