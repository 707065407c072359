//! The claims of README.md: its accuracy bullets, from the damping and modal damping studies'
//! CSVs.

use super::claims::Claims;
use super::damping;
use super::modal_damping;

pub fn claims() -> Claims {
    let mut c = Claims::new("README.md");
    c.only_section(
        "Accuracy and speed",
        "the README's other sections are the front door (commands, quick starts, variables, \
         platforms, layout, limits): settings and measured limits, not study results",
    );
    c.skip_block(
        "- **Speed**",
        "µs per step, each one measurement session (docs/speed.md gives its command, rounds, date \
         and load), with no committed bench record to check it against",
    );
    c.skip_block("| regime |", "the speed table of the bullet above");
    damping::readme(&mut c);
    modal_damping::readme(&mut c);
    c
}
