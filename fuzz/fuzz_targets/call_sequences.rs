//! Call sequences of both FMI versions, driven by the fuzzer's bytes (which call, which values
//! and value references, which step sizes), through the exported C functions under the oracles
//! of `plate_impact_host_check` (the random call-sequence test's).
//!
//! Input: a flags byte (bit 0: FMI 3.0, bit 1: start from a running simulation), then calls
//! until the bytes run out (at most 64). Values come from the host's tables most of the time
//! and as raw bits otherwise; integers and step sizes from the tables only, so that no input
//! asks for a mesh or a step whose cost would pass for a hang.

#![no_main]

use libfuzzer_sys::arbitrary::{Result, Unstructured};
use libfuzzer_sys::fuzz_target;
use plate_impact_host_check::{
    fuzz_init, fuzz_sequence, value_references, Op, INTEGERS, REALS, SIZES, SLOTS, STEPS, TEXTS, TIMES,
};
use plate_impact::fmi::variables::{Description, Kind, FMI2, FMI3};

/// At most this many calls per input (the random test draws up to 40).
const MOST_CALLS: usize = 64;

/// A table's value three times in four, else raw bits.
fn real(u: &mut Unstructured, table: &[f64]) -> Result<f64> {
    if u.ratio(3, 4)? {
        u.choose(table).copied()
    } else {
        Ok(f64::from_bits(u.arbitrary()?))
    }
}

/// A value reference of `kind` fifteen times in sixteen, else any.
fn reference(u: &mut Unstructured, d: &Description, kind: Kind) -> Result<u32> {
    if u.ratio(15, 16)? {
        u.choose(&value_references(d, kind)).copied()
    } else {
        u.arbitrary()
    }
}

/// One to three (value reference, value) pairs.
fn items<T>(
    u: &mut Unstructured,
    d: &Description,
    kind: Kind,
    value: impl Fn(&mut Unstructured) -> Result<T>,
) -> Result<Vec<(u32, T)>> {
    let n = u.int_in_range(1..=3)?;
    (0..n)
        .map(|_| Ok((reference(u, d, kind)?, value(u)?)))
        .collect()
}

fn op(u: &mut Unstructured, d: &Description) -> Result<Op> {
    let slot = |u: &mut Unstructured| u.choose_index(SLOTS);
    Ok(match u.int_in_range(0..=18u8)? {
        0 => Op::SetupExperiment(
            real(u, TIMES)?,
            u.arbitrary::<bool>()?.then_some(real(u, TIMES)?),
        ),
        1 => Op::EnterInitialization,
        2 => Op::ExitInitialization,
        3 => Op::Configuration(u.arbitrary()?),
        4 => Op::Terminate,
        5 => Op::Reset,
        6 | 7 => Op::SetReal(items(u, d, Kind::Real, |u| real(u, REALS))?),
        8 => Op::SetInteger(items(u, d, Kind::Integer, |u| u.choose(INTEGERS).copied())?),
        9 => Op::SetUInt64(items(u, d, Kind::UInt64, |u| {
            if u.ratio(3, 4)? {
                u.choose(SIZES).copied()
            } else {
                u.arbitrary()
            }
        })?),
        10 => Op::SetBoolean(items(u, d, Kind::Boolean, |u| u.arbitrary())?),
        11 | 12 => Op::DoStep(*u.choose(STEPS)?, u.ratio(1, 10)?),
        13 => Op::Derivative(u.int_in_range(-1..=3)?, real(u, REALS)?),
        14 => Op::SaveState(slot(u)?),
        15 => Op::RestoreState(slot(u)?),
        16 => match u.int_in_range(0..=2u8)? {
            0 => Op::SerializeRoundTrip(slot(u)?),
            _ => Op::CorruptState(slot(u)?, u.arbitrary()?, u.int_in_range(1..=255)?),
        },
        17 => Op::Logging(u.arbitrary()?, u.arbitrary()?),
        _ => Op::SetString(items(u, d, Kind::String, |u| {
            u.choose(TEXTS).map(|t| t.to_string())
        })?),
    })
}

fn ops(u: &mut Unstructured, d: &Description) -> Result<Vec<Op>> {
    let mut ops = Vec::new();
    while !u.is_empty() && ops.len() < MOST_CALLS {
        ops.push(op(u, d)?);
    }
    Ok(ops)
}

fuzz_target!(
    init: fuzz_init(),
    |data: &[u8]| {
    let Some((&flags, rest)) = data.split_first() else {
        return;
    };
    let (fmi3, running) = (flags & 1 != 0, flags & 2 != 0);
    let mut u = Unstructured::new(rest);
    let d = if fmi3 { &FMI3 } else { &FMI2 };
    let Ok(ops) = ops(&mut u, d) else {
        return;
    };
    fuzz_sequence(fmi3, running, &ops);
});
