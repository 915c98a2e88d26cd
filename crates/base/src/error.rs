//! Errors of the model library.

use std::fmt;

/// A value in a scenario (or any user input) that is not allowed.
#[derive(Debug, Clone, PartialEq)]
pub struct InvalidValue {
    /// Dotted path of the field, e.g. `demand.pulses[1].peak_dm3_s`.
    pub field: String,
    /// The value given, as the user wrote it (display units).
    pub value: String,
    /// What is allowed.
    pub allowed: String,
}

impl fmt::Display for InvalidValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "`{}` = {} is not allowed: {}",
            self.field, self.value, self.allowed
        )
    }
}

/// Errors of this crate.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A field (of a scenario, a model spec, a command's option) has a value out of range.
    #[error("invalid {}: {value}", scenario.as_ref().map(|s| format!("scenario `{s}`")).unwrap_or_else(|| "value".into()))]
    Invalid {
        /// The field, its value and what is allowed.
        value: InvalidValue,
        /// The scenario's name, when known.
        scenario: Option<String>,
    },
    /// The scenario file is not valid TOML for a scenario (syntax, unknown key, type).
    #[error("cannot read scenario {source_name}: {message}")]
    Parse {
        /// File name or scenario name.
        source_name: String,
        /// What the TOML reader said (it names the line and the key).
        message: String,
    },
    /// No shipped scenario of that name and no such file.
    #[error("unknown scenario `{name}`: not a file, and not one of the shipped scenarios ({known})")]
    UnknownScenario {
        /// The name given.
        name: String,
        /// The shipped names.
        known: String,
    },
    /// A file could not be read.
    #[error("cannot read {path}: {message}")]
    Io {
        /// Path.
        path: String,
        /// The system's message.
        message: String,
    },
    /// The solver failed; the state is named in display units.
    #[error("simulation failed at t = {t_s} s ({state}): {source}")]
    Solver {
        /// Time \[s\].
        t_s: f64,
        /// The state, named and in display units.
        state: String,
        /// The solver's error.
        source: Box<rhonn_ode::Error>,
    },
    /// A computed result (a fitted weight, a figure) is NaN or infinite; `cause` says what
    /// in the data or the settings led there.
    #[error("{what} is not finite (NaN or infinity): {cause}")]
    NotFinite {
        /// What was computed, e.g. "the fitted model's weights".
        what: String,
        /// The likely cause, in terms of the data and the settings.
        cause: String,
    },
    /// An argument of a library call (not a file's field) is out of range; the message
    /// names it, its value and what is allowed.
    #[error("{0}")]
    Argument(String),
    /// The call was asked to stop (`crate::cancel`: Python's Ctrl-C) and did.
    #[error("interrupted")]
    Interrupted,
    /// A controller produced a non-finite output or weight.
    #[error("controller diverged at t = {t_s} s ({state})")]
    Controller {
        /// Time \[s\].
        t_s: f64,
        /// The plant's and the controller's state, in display units.
        state: String,
    },
}

/// What kind of failure an error is, for a caller that maps errors onto its own (Python's
/// exception classes, an exit code).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// The caller gave something not allowed: a value, a file's content, a name.
    Input,
    /// A file could not be read or written.
    Io,
    /// A step failed while running (a solver, a diverging controller).
    Failed,
}

impl Error {
    /// Its kind.
    pub fn kind(&self) -> ErrorKind {
        match self {
            Error::Invalid { .. }
            | Error::Parse { .. }
            | Error::UnknownScenario { .. }
            | Error::Argument(_) => ErrorKind::Input,
            Error::Io { .. } => ErrorKind::Io,
            _ => ErrorKind::Failed,
        }
    }
}

/// Result alias.
pub type Result<T, E = Error> = std::result::Result<T, E>;

impl Error {
    /// This error with an invalid value's field `from` named `to` instead: a caller whose
    /// argument has another name (Python's `select_steps_ahead` for `--select-steps-ahead`).
    pub fn with_field_named(self, from: &str, to: &str) -> Error {
        match self {
            Error::Invalid { mut value, scenario } if value.field == from => {
                value.field = to.to_string();
                Error::Invalid { value, scenario }
            }
            e => e,
        }
    }
}

/// Shorthand to build [`Error::Invalid`].
pub fn invalid(field: impl Into<String>, value: impl fmt::Display, allowed: impl Into<String>) -> Error {
    Error::Invalid {
        value: InvalidValue {
            field: field.into(),
            value: readable(value.to_string()),
            allowed: allowed.into(),
        },
        scenario: None,
    }
}

/// `e` with its field named from `root` (e.g. `baseline`) instead of `model`: a model
/// checked on its own, which a file holds under another key.
pub fn rerooted(e: Error, root: &str) -> Error {
    match e {
        Error::Invalid { mut value, scenario } => {
            value.field = match value.field.strip_prefix("model.") {
                Some(rest) => format!("{root}.{rest}"),
                None => format!("{root}: {}", value.field),
            };
            Error::Invalid { value, scenario }
        }
        other => other,
    }
}

/// What is wrong with `path`, in words a user can act on, for an input/output error `e`
/// met while reading or writing it: whether the path is missing (and whether its folder
/// is), a folder where a file is wanted (or the other way round), or not writable.
pub fn path_problem(path: &std::path::Path, e: &std::io::Error) -> String {
    use std::io::ErrorKind;
    let parent = path.parent().filter(|p| !p.as_os_str().is_empty());
    let base = match e.kind() {
        _ if path.is_dir() => "it is a directory, not a file".to_string(),
        ErrorKind::NotFound => match parent {
            Some(p) if !p.exists() => format!("its folder {} does not exist", p.display()),
            Some(p) if !p.is_dir() => format!("{} is a file, not a folder", p.display()),
            _ => "no such file".to_string(),
        },
        ErrorKind::PermissionDenied => {
            "permission denied (not readable or not writable by this user)".to_string()
        }
        _ => match parent {
            Some(p) if p.exists() && !p.is_dir() => format!("{} is a file, not a folder", p.display()),
            _ => e.to_string(),
        },
    };
    if base == e.to_string() {
        base
    } else {
        format!("{base} ({e})")
    }
}

/// The most bytes of a scenario, spec or model file read ([`read_text`]).
pub const MAX_TEXT_BYTES: u64 = 256 << 20;
/// The longest line of a recording read ([`LineLimited`]).
pub const MAX_LINE_BYTES: usize = 1 << 20;

/// A user's text file (a scenario, spec or model.json), at most [`MAX_TEXT_BYTES`]:
/// a larger one, or an endless stream such as `/dev/zero`, is an error instead of filling
/// the memory (found by hand: `rhonn run /dev/zero` ran until it was killed). Pipes
/// (`<(zcat f)`) are read as files are.
pub fn read_text(path: &std::path::Path) -> std::io::Result<String> {
    use std::io::Read;
    let mut bytes = Vec::new();
    std::fs::File::open(path)?
        .take(MAX_TEXT_BYTES + 1)
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > MAX_TEXT_BYTES {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            "more than 256 MiB: not a scenario, spec or model file",
        ));
    }
    String::from_utf8(bytes).map_err(|_| {
        std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            "stream did not contain valid UTF-8",
        )
    })
}

/// A reader that fails on a line longer than [`MAX_LINE_BYTES`]: a recording read
/// through it is refused, not read into memory for ever, when it has no line ends (a
/// binary file, `/dev/zero`; found by hand).
pub struct LineLimited<R> {
    inner: R,
    since_newline: usize,
}

impl<R> LineLimited<R> {
    /// Wrap `inner`.
    pub fn new(inner: R) -> Self {
        LineLimited {
            inner,
            since_newline: 0,
        }
    }
}

impl<R: std::io::Read> std::io::Read for LineLimited<R> {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        let n = self.inner.read(buf)?;
        for &b in &buf[..n] {
            self.since_newline = if b == b'\n' { 0 } else { self.since_newline + 1 };
            if self.since_newline > MAX_LINE_BYTES {
                return Err(std::io::Error::new(
                    std::io::ErrorKind::InvalidData,
                    "a line longer than 1 MiB: not a CSV recording",
                ));
            }
        }
        Ok(n)
    }
}

/// A number written out in more than 20 characters (`1e300` prints 301 digits) with 10
/// significant digits; any other value as it is.
pub fn readable(value: String) -> String {
    match value.parse::<f64>() {
        Ok(v) if value.len() > 20 => crate::metrics::sig(v, 10),
        _ => value,
    }
}

#[cfg(test)]
mod path_tests {
    use super::path_problem;
    use std::io::{Error, ErrorKind};

    #[test]
    fn path_problems_say_what_the_path_is() {
        let d = tempfile::tempdir().unwrap();
        let nf = Error::from(ErrorKind::NotFound);
        assert!(path_problem(d.path(), &nf).starts_with("it is a directory"));
        assert!(path_problem(&d.path().join("x.csv"), &nf).starts_with("no such file"));
        let deep = d.path().join("no/x.csv");
        assert!(
            path_problem(&deep, &nf).contains("folder")
                && path_problem(&deep, &nf).contains("does not exist")
        );
        std::fs::write(d.path().join("f"), "").unwrap();
        let under_file = d.path().join("f/x.csv");
        let e = std::fs::write(&under_file, "").unwrap_err();
        assert!(
            path_problem(&under_file, &e).contains("is a file, not a folder"),
            "{}",
            path_problem(&under_file, &e)
        );
        let pd = Error::from(ErrorKind::PermissionDenied);
        assert!(path_problem(&d.path().join("x"), &pd).starts_with("permission denied"));
    }

    #[test]
    fn a_line_longer_than_the_limit_fails_the_read_and_short_lines_pass() {
        use std::io::Read;
        let long = vec![b'0'; super::MAX_LINE_BYTES + 1];
        let mut out = Vec::new();
        let e = super::LineLimited::new(&long[..])
            .read_to_end(&mut out)
            .unwrap_err();
        assert!(e.to_string().contains("longer than 1 MiB"), "{e}");
        let mut ok = Vec::new();
        for _ in 0..3 {
            ok.extend(vec![b'1'; super::MAX_LINE_BYTES]);
            ok.push(b'\n');
        }
        let mut out = Vec::new();
        super::LineLimited::new(&ok[..]).read_to_end(&mut out).unwrap();
        assert_eq!(out, ok);
    }

    #[test]
    fn a_huge_value_in_an_error_is_written_with_significant_digits() {
        let e = super::invalid("gain0", -1.7e308, "at most 1e6").to_string();
        assert!(e.contains("`gain0` = -1.7e308 is not allowed"), "{e}");
        let e = super::invalid("x", 0.125, "below 0.1").to_string();
        assert!(e.contains("`x` = 0.125 is"), "{e}");
        let e = super::invalid("name", "a very long name that is not a number at all", "short").to_string();
        assert!(e.contains("a very long name that is not a number at all"), "{e}");
    }
}
