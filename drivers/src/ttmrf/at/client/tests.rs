//! Scripted tests of the configuration client against the manual's message sequences.
use super::*;
use crate::ttmrf::at::settings::DecodedProtocol;

/// Collects the client's outputs as text: "> line" sent, "@baud" switches, "done"/"fail".
fn drain(c: &mut ConfigClient) -> Vec<String> {
    std::iter::from_fn(|| c.poll_output())
        .map(|o| match o {
            Output::Send(b) => format!("> {}", String::from_utf8(b).unwrap().trim_end()),
            Output::SetBaud(b) => format!("@{b}"),
            Output::Finished(Ok(_)) => "done".into(),
            Output::Finished(Err(e)) => format!("fail: {}", e.error),
        })
        .collect()
}

fn feed(c: &mut ConfigClient, lines: &str, now: Duration) -> Vec<String> {
    c.handle_bytes(lines.as_bytes(), now);
    drain(c)
}

#[test]
fn scripted_happy_path_follows_the_manual() {
    let ms = Duration::from_millis;
    let mut c = ConfigClient::new(
        vec![Setting::adsb_decoded(DecodedProtocol::Csv)],
        ClientConfig::default(),
    );
    c.start(ms(0));
    assert_eq!(drain(&mut c), ["@921600", "> AT+CONFIG=1"]);
    // 5.1.8 shows AT+OK first; 4.2.2 AT+RUN_END at the RUN baud: either moves to 115200.
    assert_eq!(feed(&mut c, "AT+OK\r\n", ms(1)), ["@115200"]);
    assert_eq!(
        feed(&mut c, "AT+CONFIG_START\r\n", ms(2)),
        ["> AT+SERIAL_NUMBER?"]
    );
    assert_eq!(
        feed(&mut c, "AT+SERIAL_NUMBER=07-0001337\r\n", ms(3)),
        ["> AT+FIRMWARE_VERSION?"]
    );
    assert_eq!(
        feed(
            &mut c,
            "AT+FIRMWARE_VERSION=2.73.1.0 (Jun 27 2024)\r\n",
            ms(4)
        ),
        ["> AT+BAUDRATE?"]
    );
    // BAUDRATE 2: the module will come back at 3 Mbps.
    assert_eq!(
        feed(&mut c, "AT+BAUDRATE=2\r\n", ms(5)),
        ["> AT+ADSB_RX_PROTOCOL_DECODED?"]
    );
    assert_eq!(
        feed(&mut c, "AT+ADSB_RX_PROTOCOL_DECODED=3\r\n", ms(6)),
        ["> AT+ADSB_RX_PROTOCOL_DECODED=1"]
    );
    assert_eq!(
        feed(&mut c, "AT+OK\r\n", ms(7)),
        ["> AT+ADSB_RX_PROTOCOL_DECODED?"]
    );
    // Case-insensitive name match on the read-back.
    assert_eq!(
        feed(&mut c, "AT+adsb_rx_protocol_decoded=1\r\n", ms(8)),
        ["> AT+LOCK=0"]
    );
    assert_eq!(feed(&mut c, "AT+OK\r\n", ms(9)), ["> AT+CONFIG=0"]);
    assert_eq!(
        feed(&mut c, "AT+OK\r\nAT+CONFIG_END\r\n", ms(10)),
        ["@3000000"]
    );
    assert_eq!(feed(&mut c, "AT+RUN_START\r\n", ms(11)), ["done"]);
    assert!(c.is_finished());
    assert_eq!(c.poll_timeout(), None);
}

#[test]
fn timeouts_and_retries_are_bounded() {
    let cfg = ClientConfig {
        attempts: 2,
        ..Default::default()
    };
    let mut c = ConfigClient::new(vec![Setting::gnss_nmea(true)], cfg);
    let mut now = Duration::ZERO;
    c.start(now);
    let mut log = drain(&mut c);
    // Nobody answers: run the timers until the client gives up.
    for _ in 0..100 {
        let Some(t) = c.poll_timeout() else { break };
        now = t;
        c.handle_timeout(now);
        log.extend(drain(&mut c));
    }
    assert_eq!(
        log.last().map(String::as_str),
        Some("fail: ttmrf control: module did not enter configuration state after 2 attempts")
    );
    // Two entry attempts (each CONFIG=1 at the RUN baud, then a CONFIG? probe at 115200),
    // then the clean-up at 115200 (2 x LOCK=0, 2 x CONFIG=0), back at the RUN baud.
    let sent: Vec<&str> = log
        .iter()
        .filter(|l| l.starts_with('>'))
        .map(String::as_str)
        .collect();
    assert_eq!(
        sent,
        [
            "> AT+CONFIG=1",
            "> AT+CONFIG?",
            "> AT+CONFIG=1",
            "> AT+CONFIG?",
            "> AT+LOCK=0",
            "> AT+LOCK=0",
            "> AT+CONFIG=0",
            "> AT+CONFIG=0",
        ]
    );
    assert_eq!(log[log.len() - 2], "@921600");
    // 2 x (3 s + 0.5 s) + 2 x 0.5 s + 2 x 3 s = 14 s.
    assert_eq!(now, Duration::from_secs(14));
}

#[test]
fn rejected_write_cleans_up() {
    let ms = Duration::from_millis;
    let mut c = ConfigClient::new(vec![Setting::gnss_nmea(true)], ClientConfig::default());
    c.start(ms(0));
    drain(&mut c);
    for line in [
        "AT+RUN_END\r\n",
        "AT+CONFIG_START\r\n",
        "AT+SERIAL_NUMBER=1\r\n",
        "AT+FIRMWARE_VERSION=2\r\n",
        "AT+BAUDRATE=0\r\n",
        "AT+GNSS_RX_PROTOCOL_RAW=0\r\n",
    ] {
        feed(&mut c, line, ms(1));
    }
    assert_eq!(
        feed(&mut c, "AT+ERROR (No GNSS on this variant)\r\n", ms(2)),
        ["> AT+LOCK=0"]
    );
    assert_eq!(feed(&mut c, "AT+OK\r\n", ms(3)), ["> AT+CONFIG=0"]);
    // BAUDRATE 0 = 115200: no baud change on the way out.
    assert_eq!(
        feed(&mut c, "AT+CONFIG_END\r\n", ms(4)),
        Vec::<String>::new()
    );
    assert_eq!(
        feed(&mut c, "AT+RUN_START\r\n", ms(5)),
        ["fail: ttmrf control: AT+GNSS_RX_PROTOCOL_RAW=5 rejected: No GNSS on this variant"]
    );
}
