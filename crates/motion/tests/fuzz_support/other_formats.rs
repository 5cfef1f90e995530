//! Valid ESM, K-NET and COSMOS files for `fuzz_records.rs`: random values
//! in gal written with the headers each database writes, LF or CRLF.

use proptest::collection::vec;
use proptest::prelude::*;

/// Tokens of ESM, K-NET, COSMOS and labelled text files, good and bad.
pub const TOKENS: &[&str] = &[
    "EVENT_NAME:",
    "SAMPLING_INTERVAL_S: 0.01",
    "NDATA: 3",
    "UNITS: cm/s^2",
    "DATA_TYPE: ACCELERATION",
    "PGA_CM/S^2: 1e400",
    "Origin Time",
    "Sampling Freq(Hz) 100Hz",
    "Scale Factor 3920(gal)/6182761",
    "Scale Factor 1(gal)/0",
    "Max. Acc. (gal) 0",
    "Dir. U-D",
    "Memo.",
    "Corrected acceleration  (Format v01.20 with 13 text lines)",
    "(Format v01.20 with 99999999999 text lines)",
    "(Format v01.20 with 18446744073709551615 text lines)",
    "18446744073709551615 Comment line(s) follow",
    "100 Integer-header values follow on 10 lines, Format= (10I8)",
    "100 Real-header values follow on 17 lines, Format= (6F13.6)",
    "99999999999 Real-header values follow",
    "1 Comment line(s) follow",
    "3 acceleration pts, approx 0 secs, units=cm/sec2 (04), Format=(8F10.5)",
    "Format=(0F0.0)",
    "Format=(99999999999999999999F10.5)",
    "0,5",
    "-90.15800-109.02749",
    "acc_m_s2",
    "acc [g]",
    "time_ms",
];

/// A valid ESM, K-NET or COSMOS file: its text, format and file name.
#[derive(Debug, Clone)]
pub struct ValidOther {
    pub text: String,
    pub file: &'static str,
    pub count: usize,
}

pub fn valid_other() -> impl Strategy<Value = ValidOther> {
    (vec(-600.0f64..600.0, 2..200), 0usize..3, any::<bool>()).prop_map(|(gal, kind, crlf)| {
        let n = gal.len();
        let (file, text) = match kind {
            0 => {
                let body: Vec<String> = gal.iter().map(|v| format!("{v:.6E}")).collect();
                let text = format!(
                    "EVENT_NAME: F\nEVENT_ID: X\nSAMPLING_INTERVAL_S: 0.005000\nNDATA: {n}\nSTREAM: HGE\n\
                     UNITS: cm/s^2\nPGA_CM/S^2: 100\nDATA_TYPE: ACCELERATION\nUSER5: \n{}\n",
                    body.join("\n")
                );
                ("f.ASC", text)
            }
            1 => {
                let counts: Vec<String> = gal
                    .chunks(8)
                    .map(|c| c.iter().map(|v| format!("{:9}", (v * 1000.0).round() as i64 + 1234)).collect())
                    .collect();
                let text = format!(
                    "Origin Time       2000/01/01 00:00:00\nSampling Freq(Hz) 100Hz\nDuration Time(s)  1\n\
                     Dir.              N-S\nScale Factor      1(gal)/1000\nMax. Acc. (gal)   100\nMemo.\n{}\n",
                    counts.join("\n")
                );
                ("f.EW", text)
            }
            _ => {
                let mut t = String::from("Corrected acceleration  (Format v01.20 with 13 text lines)\n");
                for i in 2..=12 {
                    t += &format!("line {i}\n");
                }
                t += "Values used when parameter or data value is unknown/unspecified:   -999, -999.0\n";
                t += " 100 Integer-header values follow on 10 lines, Format= (10I8)\n";
                let mut ints = [-999i64; 100];
                (ints[1], ints[2]) = (1, 4);
                for row in ints.chunks(10) {
                    t += &(row.iter().map(|v| format!("{v:8}")).collect::<String>() + "\n");
                }
                t += " 100 Real-header values follow on 17 lines, Format= (6F13.6)\n";
                let mut reals = [-999.0f64; 100];
                reals[61] = 5.0;
                for row in reals.chunks(6) {
                    t += &(row.iter().map(|v| format!("{v:13.6}")).collect::<String>() + "\n");
                }
                t += "   1 Comment line(s) follow, each starting with a \"|\":\n| c\n";
                t += &format!("{n:8} acceleration pts, approx    1 secs, units=cm/sec2 (04), Format=(8F10.5)\n");
                for c in gal.chunks(8) {
                    t += &(c.iter().map(|v| format!("{v:10.5}")).collect::<String>() + "\n");
                }
                ("f.V2", t + "End-of-data for Chan  1 acceleration\n")
            }
        };
        let text = if crlf { text.replace('\n', "\r\n") } else { text };
        ValidOther { text, file, count: n }
    })
}
