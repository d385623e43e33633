//! A sans-IO command client for configuring the VN-200 (ICD 1.3, Registers 75-77).
//!
//! It queues commands, hands out the bytes to send ([`ConfigClient::poll_transmit`]), matches
//! each answer — the echo of the command or a `$VNERR` — as it is decoded
//! ([`ConfigClient::handle_message`]), resends after a timeout, gives up after a number of
//! attempts, and reports the outcome of every command ([`ConfigClient::report`]). Time is passed
//! in as `now` (any monotonic clock, as a [`Duration`] since its epoch): the client reads no clock
//! and touches no port, in the style of quinn-proto.
//!
//! Matching: a `$VNWRG` is answered by an echo of the same register (the register's new
//! contents; a difference from what was written is reported, not treated as failure); other
//! commands by an echo of the same header. A `$VNERR` received while a command is waiting is
//! taken as that command's answer (the sensor answers commands in order and sends nothing else
//! that is an error unless ErrorMode reports system errors, which then fail the command: the
//! safe reading for a configuration step). VNBOM is not echoed and is not accepted here.

use std::collections::VecDeque;
use std::time::Duration;

use serde::Serialize;

use super::ascii::{
    AsciiMessage, BinaryOutputConfig, ChecksumKind, Command, ErrorCode, RegisterValue,
};
use super::decoder::Vn200Message;

/// What happened to one command.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "outcome", rename_all = "snake_case")]
pub enum Outcome {
    /// Echoed. For a register write, `echo_matches` says whether the echoed contents equal
    /// what was written.
    Accepted {
        /// Echoed contents equal the request.
        echo_matches: bool,
    },
    /// Answered with `$VNERR`.
    Rejected {
        /// The error code.
        code: ErrorCode,
    },
    /// No answer after every attempt.
    TimedOut,
}

/// The report line of one command.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CommandReport {
    /// The command.
    pub command: Command,
    /// Times it was sent.
    pub attempts: u32,
    /// The outcome.
    pub outcome: Outcome,
}

#[derive(Debug, Clone)]
struct Waiting {
    command: Command,
    sent_at: Duration,
    attempts: u32,
}

/// Why a configuration could not be built.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ClientError {
    /// Only Registers 75, 76 and 77 hold binary output configurations.
    #[error("binary output configuration index {0} is not 1, 2 or 3")]
    BadIndex(u8),
    /// VNBOM is answered with binary data, not an echo.
    #[error("command {0} is not echoed and cannot be confirmed")]
    NotEchoed(&'static str),
}

/// The configuration client.
#[derive(Debug, Clone)]
pub struct ConfigClient {
    queue: VecDeque<Command>,
    waiting: Option<Waiting>,
    report: Vec<CommandReport>,
    timeout: Duration,
    max_attempts: u32,
    checksum: ChecksumKind,
}

impl ConfigClient {
    /// A client that waits `timeout` for each answer and sends each command at most
    /// `max_attempts` times (at least once).
    pub fn new(timeout: Duration, max_attempts: u32) -> Self {
        Self {
            queue: VecDeque::new(),
            waiting: None,
            report: Vec::new(),
            timeout,
            max_attempts: max_attempts.max(1),
            checksum: ChecksumKind::Xor8,
        }
    }

    /// Chooses the checksum style of the commands (the sensor's Register 30 setting).
    pub fn with_checksum(mut self, kind: ChecksumKind) -> Self {
        self.checksum = kind;
        self
    }

    /// Queues a command.
    pub fn push(&mut self, command: Command) -> Result<(), ClientError> {
        if !command.is_echoed() {
            return Err(ClientError::NotEchoed(command.header()));
        }
        self.queue.push_back(command);
        Ok(())
    }

    /// Queues the write of binary output configuration `index` (1-3 = Register 75-77) for the
    /// given type masks (table offsets, indexed by group offset), sent on the ports in
    /// `async_mode` every `rate_divisor` IMU samples.
    pub fn configure_binary_output(
        &mut self,
        index: u8,
        async_mode: u16,
        rate_divisor: u16,
        masks: [u32; 7],
    ) -> Result<(), ClientError> {
        if !(1..=3).contains(&index) {
            return Err(ClientError::BadIndex(index));
        }
        let config = BinaryOutputConfig::from_masks(async_mode, rate_divisor, masks);
        self.push(Command::WriteRegister(RegisterValue::BinaryOutput {
            index,
            config,
        }))
    }

    /// A whole set-up session: pause async outputs on this port (VNASY,0) so that answers are
    /// easy to see, write each binary output configuration `(index, async_mode, rate_divisor,
    /// masks)`, optionally save to flash (VNWNV), and resume async outputs (VNASY,1).
    pub fn setup_session(
        timeout: Duration,
        max_attempts: u32,
        outputs: &[(u8, u16, u16, [u32; 7])],
        save: bool,
    ) -> Result<Self, ClientError> {
        let mut c = Self::new(timeout, max_attempts);
        c.push(Command::AsyncOutputEnable(false))?;
        for &(index, mode, divisor, masks) in outputs {
            c.configure_binary_output(index, mode, divisor, masks)?;
        }
        if save {
            c.push(Command::WriteSettings)?;
        }
        c.push(Command::AsyncOutputEnable(true))?;
        Ok(c)
    }

    /// Bytes to send now, if any: the next command, or a resend of the waiting one whose answer
    /// is overdue. Also records a timeout when the last attempt has expired.
    pub fn poll_transmit(&mut self, now: Duration) -> Option<Vec<u8>> {
        if let Some(w) = &mut self.waiting {
            if now.saturating_sub(w.sent_at) < self.timeout {
                return None;
            }
            if w.attempts < self.max_attempts {
                w.attempts += 1;
                w.sent_at = now;
                return Some(w.command.encode(self.checksum));
            }
            let w = self.waiting.take()?;
            self.report.push(CommandReport {
                command: w.command,
                attempts: w.attempts,
                outcome: Outcome::TimedOut,
            });
        }
        let command = self.queue.pop_front()?;
        let bytes = command.encode(self.checksum);
        self.waiting = Some(Waiting {
            command,
            sent_at: now,
            attempts: 1,
        });
        Some(bytes)
    }

    /// When [`ConfigClient::poll_transmit`] next needs calling (the waiting command's deadline),
    /// or `None` if nothing is waiting.
    pub fn poll_timeout(&self) -> Option<Duration> {
        self.waiting.as_ref().map(|w| w.sent_at + self.timeout)
    }

    /// Offers a decoded message. Returns true if it answered the waiting command.
    pub fn handle_message(&mut self, msg: &Vn200Message, _now: Duration) -> bool {
        let Some(w) = &self.waiting else {
            return false;
        };
        let Vn200Message::Ascii(a) = msg else {
            return false;
        };
        let outcome = match a {
            AsciiMessage::Error { code } => Outcome::Rejected { code: *code },
            AsciiMessage::Command { command } => match (&w.command, command) {
                (Command::WriteRegister(sent), Command::WriteRegister(echo)) => {
                    if sent.id() != echo.id() {
                        return false;
                    }
                    Outcome::Accepted {
                        echo_matches: sent == echo,
                    }
                }
                (sent, echo) if sent.header() == echo.header() => Outcome::Accepted {
                    echo_matches: sent == echo,
                },
                _ => return false,
            },
            AsciiMessage::ReadResponse { value } => match &w.command {
                Command::ReadRegister(id) if *id == value.id() => {
                    Outcome::Accepted { echo_matches: true }
                }
                _ => return false,
            },
            AsciiMessage::Async(_) => return false,
        };
        let Some(w) = self.waiting.take() else {
            return false;
        };
        self.report.push(CommandReport {
            command: w.command,
            attempts: w.attempts,
            outcome,
        });
        true
    }

    /// Whether every command has an outcome.
    pub fn is_done(&self) -> bool {
        self.waiting.is_none() && self.queue.is_empty()
    }

    /// Whether every finished command was accepted with a matching echo.
    pub fn all_accepted(&self) -> bool {
        self.report
            .iter()
            .all(|r| r.outcome == Outcome::Accepted { echo_matches: true })
    }

    /// The outcomes so far, in order.
    pub fn report(&self) -> &[CommandReport] {
        &self.report
    }
}

#[cfg(test)]
mod tests;
