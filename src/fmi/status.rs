//! Function results of the FMI layer: the status codes FMI defines and the failures that carry a
//! message for the log.

/// The status codes of FMI (fmi2Status; FMI 3.0 uses the same values without `Pending`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Status {
    /// All well.
    Ok = 0,
    /// Done, but something the user should know was logged.
    Warning = 1,
    /// Not done, the instance is as before the call (status queries this FMU cannot answer).
    Discard = 2,
    /// Not done.
    Error = 3,
    /// The instance is unusable.
    Fatal = 4,
    /// An asynchronous step is running (never returned by this FMU).
    Pending = 5,
}

/// What a failed call leaves behind.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Aftermath {
    /// The call was refused before it changed anything: the instance stays as it was.
    Unchanged,
    /// The call failed part-way (a step that could not be completed): the instance goes to the
    /// Error state, from which the host restores an FMU state, resets or frees it.
    Broken,
}

/// A failed call: the status to return, the message for the log, and what it leaves behind.
#[derive(Clone, Debug, PartialEq)]
pub struct Failure {
    /// fmi2Error unless stated.
    pub status: Status,
    /// What happened and what to do, for the user.
    pub message: String,
    /// Whether the instance is unchanged or broken.
    pub aftermath: Aftermath,
}

impl Failure {
    /// A call refused with fmi2Error before it changed anything.
    pub fn refused(message: impl Into<String>) -> Failure {
        Failure {
            status: Status::Error,
            message: message.into(),
            aftermath: Aftermath::Unchanged,
        }
    }

    /// A call that failed part-way with fmi2Error: the instance goes to the Error state.
    pub fn broken(message: impl Into<String>) -> Failure {
        Failure {
            status: Status::Error,
            message: message.into(),
            aftermath: Aftermath::Broken,
        }
    }

    /// A status query answered with fmi2Discard (nothing changed).
    pub fn discarded(message: impl Into<String>) -> Failure {
        Failure {
            status: Status::Discard,
            message: message.into(),
            aftermath: Aftermath::Unchanged,
        }
    }
}

impl From<crate::Error> for Failure {
    /// A library error met while checking a call: refused, nothing changed.
    fn from(e: crate::Error) -> Failure {
        Failure::refused(e.to_string())
    }
}
