//! The `fivex serve` flags of its limits: connection timeouts and caps (`crate::listen`) and
//! how many fleet runs run at once (`docs/api.md`, "Connections and limits").

use std::time::Duration;

use clap::Args;

use crate::listen::Limits;

#[derive(Args, Debug)]
pub struct LimitArgs {
    /// Seconds a request head may take from its first byte (a new connection: from the accept).
    #[arg(long, env = "FIVEX_HEADER_TIMEOUT", default_value = "10", value_parser = seconds)]
    header_timeout: Duration,
    /// Seconds a kept-alive connection may wait for its next request.
    #[arg(long, env = "FIVEX_IDLE_TIMEOUT", default_value = "60", value_parser = seconds)]
    idle_timeout: Duration,
    /// Seconds a request body may pause while the service reads it, and a client may take
    /// nothing of an answer.
    #[arg(long, env = "FIVEX_BODY_TIMEOUT", default_value = "10", value_parser = seconds)]
    body_timeout: Duration,
    /// Open connections in all (websockets included); more are closed at once.
    #[arg(long, env = "FIVEX_MAX_CONNECTIONS", default_value_t = 10_000, value_parser = clap::value_parser!(u32).range(1..))]
    max_connections: u32,
    /// Open connections from one client address.
    #[arg(long, env = "FIVEX_MAX_CONNECTIONS_PER_CLIENT", default_value_t = 2_000, value_parser = clap::value_parser!(u32).range(1..))]
    max_connections_per_client: u32,
    /// Open websockets in all; more are refused with 503.
    #[arg(long, env = "FIVEX_MAX_WEBSOCKETS", default_value_t = 5_000, value_parser = clap::value_parser!(u32).range(1..))]
    max_websockets: u32,
    /// Open websockets from one client address; more are refused with 429.
    #[arg(long, env = "FIVEX_MAX_WEBSOCKETS_PER_CLIENT", default_value_t = 1_500, value_parser = clap::value_parser!(u32).range(1..))]
    max_websockets_per_client: u32,
    /// Fleet runs that run at once; the others wait, `queued`.
    #[arg(long, env = "FIVEX_FLEET_JOBS", default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..))]
    pub fleet_jobs: u32,
}

impl LimitArgs {
    pub fn limits(&self) -> Limits {
        Limits {
            header_timeout: self.header_timeout,
            idle_timeout: self.idle_timeout,
            body_timeout: self.body_timeout,
            max_connections: self.max_connections as usize,
            max_connections_per_client: self.max_connections_per_client as usize,
            max_websockets: self.max_websockets as usize,
            max_websockets_per_client: self.max_websockets_per_client as usize,
        }
    }
}

/// A positive number of seconds, fractions allowed (`0.5`), at most a day.
fn seconds(text: &str) -> Result<Duration, String> {
    let s: f64 = text.parse().map_err(|_| format!("'{text}' is not a number of seconds"))?;
    if !(s > 0.0 && s <= 86_400.0) {
        return Err(format!("{text} s: give more than 0 and at most 86400 seconds"));
    }
    Ok(Duration::from_secs_f64(s))
}

#[cfg(test)]
mod tests {
    use clap::Parser;

    use super::*;

    #[derive(Parser)]
    struct Flags {
        #[command(flatten)]
        limits: LimitArgs,
    }

    #[test]
    fn the_flags_defaults_are_the_documented_limits() {
        let flags = Flags::try_parse_from(["fivex"]).unwrap();
        assert_eq!(flags.limits.limits(), Limits::default());
        assert_eq!(flags.limits.fleet_jobs, 1);
    }

    #[test]
    fn seconds_take_fractions_and_refuse_nothing_or_forever() {
        let flags = Flags::try_parse_from(["fivex", "--header-timeout", "0.25"]).unwrap();
        assert_eq!(flags.limits.limits().header_timeout, Duration::from_millis(250));
        for bad in ["0", "-1", "NaN", "inf", "86401", "soon"] {
            assert!(Flags::try_parse_from(["fivex", "--idle-timeout", bad]).is_err(), "{bad}");
        }
    }
}
