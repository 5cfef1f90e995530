//! Channels of a record file: which component a record is, where it
//! points, and choosing one of several in a multi-channel file (COSMOS and
//! CSMIP files hold every channel of a station, three for a free-field
//! site, a dozen and more on a structure).

use serde::Serialize;

use crate::error::RecordError;
use crate::text::number;

/// Where a channel's sensor points.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "kebab-case")]
pub enum Orientation {
    /// Horizontal, at this azimuth [degrees clockwise from north, 0 to 360].
    Azimuth {
        /// degrees clockwise from north
        degrees: f64,
    },
    /// Vertical (up or down), as the file writes it (`Up`, `U-D`, `HNZ`).
    Vertical {
        /// as written
        label: String,
    },
    /// Along an axis of a structure (CSMIP `Long`, `Tran`), not a compass
    /// direction.
    Axis {
        /// as written
        label: String,
    },
    /// The file does not say.
    Unknown,
}

impl Orientation {
    /// In words: `90°`, `vertical (Up)`, `Long (structure axis)`, `not stated`.
    pub fn describe(&self) -> String {
        match self {
            Orientation::Azimuth { degrees } => format!("{}°", number(*degrees)),
            Orientation::Vertical { label } => format!("vertical ({label})"),
            Orientation::Axis { label } => format!("{label} (structure axis)"),
            Orientation::Unknown => "orientation not stated".into(),
        }
    }

    /// Whether the channel is vertical.
    pub fn is_vertical(&self) -> bool {
        matches!(self, Orientation::Vertical { .. })
    }

    /// A horizontal azimuth written as a number of degrees (`90`, `360`,
    /// `110 Deg`), or a word: `Up`/`Down`/`Vert`/`U-D` (vertical), `Long`,
    /// `Tran` (axes of a structure), else unknown.
    pub fn from_label(label: &str) -> Orientation {
        let words: Vec<&str> = label.split_whitespace().collect();
        let Some(first) = words.first() else { return Orientation::Unknown };
        if let Ok(d) = first.trim_end_matches(['°', ',']).parse::<f64>() {
            return if (0.0..=360.0).contains(&d) { Orientation::Azimuth { degrees: d } } else { Orientation::Unknown };
        }
        let lower = first.to_ascii_lowercase();
        if ["up", "down", "dwn", "dn", "vert", "vertical", "u-d", "ud", "z"].contains(&lower.as_str()) {
            Orientation::Vertical { label: (*first).to_string() }
        } else if lower.starts_with("long") || lower.starts_with("tran") || lower.starts_with("rad") {
            Orientation::Axis { label: (*first).to_string() }
        } else {
            Orientation::Unknown
        }
    }
}

/// One channel of a record file.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Channel {
    /// its number as the file gives it (`Chan  2:`), else its place in the
    /// file, from 1
    pub number: u32,
    /// how many channels the file holds
    pub of: u32,
    /// where it points
    pub orientation: Orientation,
}

impl Channel {
    /// `channel 2 of 3 (360°)`.
    pub fn describe(&self) -> String {
        format!("channel {} of {} ({})", self.number, self.of, self.orientation.describe())
    }
}

/// Which channel of a multi-channel file to read (the spec's `channel` and
/// `azimuth`; at most one of them).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct ChannelChoice {
    /// the channel's number as the file gives it
    pub number: Option<u32>,
    /// the channel pointing this way [degrees from north; 0 and 360 are
    /// the same]
    pub azimuth: Option<f64>,
}

/// How far apart two azimuths are [degrees, 0 to 180].
fn apart(a: f64, b: f64) -> f64 {
    let d = (a - b).rem_euclid(360.0);
    d.min(360.0 - d)
}

/// The channels, for messages: `1 (90°), 2 (360°), 3 (vertical (Up))`.
fn listing(channels: &[Channel]) -> String {
    channels.iter().map(|c| format!("{} ({})", c.number, c.orientation.describe())).collect::<Vec<_>>().join(", ")
}

/// How to choose, in the config's and the command line's words.
const HOW: &str = "choose one with `channel = N` (`--channel N`) or by its direction with `azimuth = DEGREES` \
                   (`--azimuth DEGREES`)";

/// The index (into `channels`, in file order) of the channel `choice`
/// names, with a warning when the file holds several and none was named
/// (the first is read). Errors name the channels the file holds.
pub fn choose(file: &str, channels: &[Channel], choice: ChannelChoice) -> Result<(usize, Option<String>), RecordError> {
    let spec_err = |field: &'static str, message: String| RecordError::Spec { file: file.into(), field, message };
    if channels.is_empty() {
        return Err(RecordError::TooShort { file: file.into(), message: "the file holds no channel".into() });
    }
    if let Some(n) = choice.number {
        return match channels.iter().position(|c| c.number == n) {
            Some(i) => Ok((i, None)),
            None => Err(spec_err("channel", format!("the file has no channel {n}; it holds {}", listing(channels)))),
        };
    }
    if let Some(a) = choice.azimuth {
        let close: Vec<usize> = (0..channels.len())
            .filter(|&i| matches!(channels[i].orientation, Orientation::Azimuth { degrees } if apart(degrees, a) < 0.5))
            .collect();
        return match close.as_slice() {
            [i] => Ok((*i, None)),
            [] => Err(spec_err(
                "azimuth",
                format!("no channel of the file points at {}°; it holds {}", number(a), listing(channels)),
            )),
            _ => Err(spec_err(
                "azimuth",
                format!(
                    "{} channels point at {}°: {}; choose one with `channel = N` (`--channel N`)",
                    close.len(),
                    number(a),
                    close.iter().map(|&i| channels[i].number.to_string()).collect::<Vec<_>>().join(", ")
                ),
            )),
        };
    }
    let warning = (channels.len() > 1).then(|| {
        format!(
            "{file}: the file holds {} channels, {}; the first, {}, is read: {HOW}",
            channels.len(),
            listing(channels),
            channels[0].describe()
        )
    });
    Ok((0, warning))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn three() -> Vec<Channel> {
        let c = |number, orientation| Channel { number, of: 3, orientation };
        vec![
            c(1, Orientation::from_label("90 Deg")),
            c(2, Orientation::from_label("360 Deg")),
            c(3, Orientation::from_label("Up")),
        ]
    }

    #[test]
    fn labels() {
        assert_eq!(Orientation::from_label(" 110 Deg "), Orientation::Azimuth { degrees: 110.0 });
        assert!(Orientation::from_label("UP").is_vertical());
        assert!(Orientation::from_label("U-D").is_vertical());
        assert_eq!(Orientation::from_label("Tran"), Orientation::Axis { label: "Tran".into() });
        assert_eq!(Orientation::from_label("400 Deg"), Orientation::Unknown);
        assert_eq!(Orientation::from_label(""), Orientation::Unknown);
    }

    #[test]
    fn choosing_by_number_and_by_azimuth() {
        let c = three();
        let pick = |number, azimuth| choose("f.v1", &c, ChannelChoice { number, azimuth });
        assert_eq!(pick(Some(2), None).unwrap(), (1, None));
        assert_eq!(pick(None, Some(0.0)).unwrap().0, 1, "360° is north, as 0° is");
        assert_eq!(pick(None, Some(90.2)).unwrap().0, 0);
        let e = pick(Some(7), None).unwrap_err().to_string();
        assert!(
            e.contains("field `channel`: the file has no channel 7; it holds 1 (90°), 2 (360°), 3 (vertical (Up))"),
            "{e}"
        );
        let e = pick(None, Some(45.0)).unwrap_err().to_string();
        assert!(e.contains("field `azimuth`: no channel of the file points at 45°"), "{e}");
        let (i, w) = pick(None, None).unwrap();
        let w = w.unwrap();
        assert_eq!(i, 0);
        assert!(w.contains("holds 3 channels") && w.contains("`channel = N` (`--channel N`)"), "{w}");
        assert_eq!(choose("f", &c[..1], ChannelChoice::default()).unwrap(), (0, None));
    }
}
