//! Status codes of SCIP 2.0 replies and what they mean, per command.

/// A reply whose status says the command failed.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{command}: status {status}: {meaning}")]
pub struct StatusError {
    /// The command as sent (without its line feed).
    pub command: String,
    /// The status characters.
    pub status: String,
    /// What the status means for that command.
    pub meaning: &'static str,
}

impl StatusError {
    /// The error for `status` in reply to `command`.
    #[must_use]
    pub fn new(command: &str, status: &str) -> Self {
        Self {
            command: command.to_owned(),
            status: status.to_owned(),
            meaning: meaning(command, status),
        }
    }
}

/// What `status` means in reply to `command` (a command line such as `MD0044072501000`),
/// from the SCIP 2.0 specification's tables.
#[must_use]
pub fn meaning(command: &str, status: &str) -> &'static str {
    let code = command.get(..2).unwrap_or(command);
    let specific = match (code, status) {
        (_, "00") => Some("command received without error"),
        ("MD" | "MS" | "GD" | "GS", "01") => Some("starting step is not a number"),
        ("MD" | "MS" | "GD" | "GS", "02") => Some("end step is not a number"),
        ("MD" | "MS" | "GD" | "GS", "03") => Some("cluster count is not a number"),
        ("MD" | "MS" | "GD" | "GS", "04") => Some("end step is out of range"),
        ("MD" | "MS" | "GD" | "GS", "05") => Some("end step is smaller than starting step"),
        ("MD" | "MS", "06") => Some("scan interval is not a number"),
        ("MD" | "MS", "07") => Some("number of scans is not a number"),
        ("MD" | "MS", "98") => {
            Some("measurement resumed after the sensor confirmed normal laser operation")
        }
        ("MD" | "MS", "99") => Some("scan data follow"),
        ("GD" | "GS", "10") => Some("the laser is off (send BM first)"),
        ("BM", "01") => Some("the laser cannot be switched on: laser malfunction"),
        ("BM", "02") => Some("the laser is already on"),
        ("TM", "01") => Some("invalid control code"),
        ("TM", "02") => Some("adjust mode on requested while adjust mode is already on"),
        ("TM", "03") => Some("adjust mode off requested while adjust mode is already off"),
        ("TM", "04") => Some("time requested while adjust mode is off"),
        _ => None,
    };
    if let Some(m) = specific {
        return m;
    }
    match status {
        "0A" => "the sensor could not create the reply internally",
        "0B" => "buffer shortage, or a command repeated that is already processed",
        "0C" => "command with insufficient parameters",
        "0D" | "0E" => "undefined command",
        "0F" => "command with insufficient parameters, or not supported by this sensor",
        "0G" => "the string characters of the command exceed 16 letters",
        "0H" => "the string characters of the command have invalid letters",
        "0I" => "the sensor is in firmware update mode",
        "0L" => "the sensor is in an abnormal state",
        "0M" => "measurement unstable (the motor or laser is not yet ready)",
        s if s.len() == 2 && ("21".."50").contains(&s) => "processing stopped to verify an error",
        s if s.len() == 2 && ("50".."98").contains(&s) => {
            "hardware trouble (laser or motor malfunction)"
        }
        _ => "unknown status",
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statuses_say_what_went_wrong() {
        assert_eq!(meaning("MD0044072501000", "04"), "end step is out of range");
        assert_eq!(
            meaning("GD0044072501", "10"),
            "the laser is off (send BM first)"
        );
        assert_eq!(
            meaning("TM1", "04"),
            "time requested while adjust mode is off"
        );
        assert_eq!(meaning("XX", "0E"), "undefined command");
        assert_eq!(
            meaning("MD0044072501000", "55"),
            "hardware trouble (laser or motor malfunction)"
        );
        assert_eq!(
            meaning("MD0044072501000", "30"),
            "processing stopped to verify an error"
        );
        assert_eq!(meaning("QT", "zz"), "unknown status");
        let e = StatusError::new("BM", "01");
        assert_eq!(
            e.to_string(),
            "BM: status 01: the laser cannot be switched on: laser malfunction"
        );
    }
}
