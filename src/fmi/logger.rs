//! The host's logger and its categories, switched with fmi2SetDebugLogging.

use super::status::Status;

/// Where the host's messages go: (status, category, message).
pub type LogSink = Box<dyn FnMut(Status, &str, &str) + Send>;

/// Category of messages about failed calls (always on unless switched off by name).
pub const LOG_ERROR: &str = "logStatusError";
/// Category of warnings (always on unless switched off by name).
pub const LOG_WARNING: &str = "logStatusWarning";
/// Category of the verbose call trace: every call and its result.
pub const LOG_ALL: &str = "logAll";

/// The host's logger and which of the model's categories are on.
pub struct Logger {
    sink: Option<LogSink>,
    categories: &'static [&'static str],
    enabled: Vec<bool>,
    initial: Vec<bool>,
}

impl Logger {
    /// A logger for `categories` (the description's `<LogCategories>`): errors and warnings are
    /// on, the others follow `logging_on` (the loggingOn argument of instantiation).
    pub fn new(
        sink: Option<LogSink>,
        categories: &'static [&'static str],
        logging_on: bool,
    ) -> Logger {
        let enabled: Vec<bool> = categories
            .iter()
            .map(|&c| c == LOG_ERROR || c == LOG_WARNING || logging_on)
            .collect();
        Logger {
            sink,
            categories,
            initial: enabled.clone(),
            enabled,
        }
    }

    /// Whether messages of `category` reach the host.
    pub fn enabled(&self, category: &str) -> bool {
        self.sink.is_some()
            && self
                .categories
                .iter()
                .position(|&c| c == category)
                .is_some_and(|i| self.enabled[i])
    }

    /// Sends one message if its category is on.
    pub fn log(&mut self, status: Status, category: &str, message: &str) {
        if self.enabled(category) {
            if let Some(sink) = self.sink.as_mut() {
                sink(status, category, message);
            }
        }
    }

    /// fmi2SetDebugLogging: switches the named categories (all of them when `names` is empty; then
    /// errors and warnings stay on) to `on`. An unknown name refuses the whole call, unchanged.
    pub fn switch(&mut self, on: bool, names: &[&str]) -> Result<(), String> {
        let mut enabled = self.enabled.clone();
        if names.is_empty() {
            for (flag, &c) in enabled.iter_mut().zip(self.categories) {
                *flag = on || c == LOG_ERROR || c == LOG_WARNING;
            }
        }
        for name in names {
            let i = self
                .categories
                .iter()
                .position(|c| c == name)
                .ok_or_else(|| {
                    format!(
                        "unknown log category {name:?}; the categories are {:?}",
                        self.categories
                    )
                })?;
            enabled[i] = on;
        }
        self.enabled = enabled;
        Ok(())
    }

    /// Back to the categories chosen at instantiation (fmi2Reset).
    pub fn reset(&mut self) {
        self.enabled = self.initial.clone();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::sync::{Arc, Mutex};

    const CATEGORIES: &[&str] = &[LOG_ERROR, LOG_WARNING, LOG_ALL, "logOther"];

    #[test]
    fn categories_switch_all_or_nothing() {
        let seen = Arc::new(Mutex::new(Vec::new()));
        let s = seen.clone();
        let sink: LogSink = Box::new(move |_, c, _| s.lock().unwrap().push(c.to_string()));
        let mut log = Logger::new(Some(sink), CATEGORIES, false);
        assert!(log.enabled(LOG_ERROR) && !log.enabled(LOG_ALL));
        assert!(log.switch(true, &["logOther", "logNothing"]).is_err());
        assert!(!log.enabled("logOther"), "a refused switch changes nothing");
        log.switch(true, &[]).unwrap();
        assert!(log.enabled(LOG_ALL) && log.enabled("logOther"));
        log.switch(false, &[]).unwrap();
        assert!(log.enabled(LOG_ERROR) && !log.enabled(LOG_ALL));
        log.log(Status::Ok, LOG_ALL, "dropped");
        log.log(Status::Error, LOG_ERROR, "kept");
        assert_eq!(*seen.lock().unwrap(), [LOG_ERROR]);
        log.switch(true, &[LOG_ALL]).unwrap();
        log.reset();
        assert!(!log.enabled(LOG_ALL));
    }
}
