//! Fixed-format numbers as Fortran writes them (COSMOS and CSMIP files):
//! the format after `Format=` (`(8F10.5)`), and the fields of a line.

use crate::text::parse_number;

/// Values per line and field width of a Fortran format `(8F10.5)`,
/// `(10I8)`, `(1E15.6)` after `Format=` on `line`.
pub(crate) fn fortran_format(line: &str) -> Option<(usize, usize)> {
    let lower = line.to_ascii_lowercase();
    let rest = lower[lower.find("format=")? + "format=".len()..].trim_start().strip_prefix('(')?;
    format_spec(rest.split(')').next()?)
}

/// Values per line and field width of the first Fortran format in
/// parentheses anywhere on `line` (`Format: (8f9.6)`, `cm/sec2. (8f10.6)`).
pub(crate) fn any_fortran_format(line: &str) -> Option<(usize, usize)> {
    line.split('(').skip(1).find_map(|rest| format_spec(rest.split(')').next()?))
}

/// `8F10.5` -> (8, 10): repeat count (1 if absent) and field width of an
/// I, F, E, G or D edit descriptor.
fn format_spec(inner: &str) -> Option<(usize, usize)> {
    let spec: String = inner.chars().filter(|c| !c.is_whitespace()).collect::<String>().to_ascii_lowercase();
    let letter = spec.find(|c: char| c.is_ascii_alphabetic())?;
    let repeat = if letter == 0 { 1 } else { spec[..letter].parse().ok()? };
    if !"ifegd".contains(&spec[letter..=letter]) {
        return None;
    }
    let rest = &spec[letter + 1..];
    let width: String = rest.chars().take_while(|c| c.is_ascii_digit()).collect();
    let tail = &rest[width.len()..];
    if !(tail.is_empty() || (tail.starts_with('.') && tail[1..].chars().all(|c| c.is_ascii_digit()))) {
        return None;
    }
    Some((repeat, width.parse().ok().filter(|&w| w > 0)?))
}

/// The numbers of a data line: its white-space separated tokens, or, if
/// one of those is not a number and the field width is known, fixed-width
/// fields (Fortran writes `1234.56789-123.45678` without a space).
pub(crate) fn fortran_tokens(line: &str, width: Option<usize>) -> Vec<&str> {
    let words: Vec<&str> = line.split_whitespace().collect();
    match width {
        Some(w) if line.is_ascii() && words.iter().any(|t| parse_number(t).is_err()) => fixed_fields(line, w),
        _ => words,
    }
}

/// The fields of `line` cut every `width` bytes (blanks around each
/// trimmed), whatever white space says: Fortran's `(16I5)` writes `  36032080`
/// for 360 and 32080. A line that is not ASCII is split at white space.
pub(crate) fn fixed_fields(line: &str, width: usize) -> Vec<&str> {
    let body = line.trim_end();
    if !body.is_ascii() || width == 0 {
        return body.split_whitespace().collect();
    }
    (0..body.len()).step_by(width).map(|a| body[a..(a + width).min(body.len())].trim()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_and_fields() {
        assert_eq!(fortran_format("Format= (10I8)"), Some((10, 8)));
        assert_eq!(fortran_format("units=cm/sec2(04),Format=(1E15.6)"), Some((1, 15)));
        assert_eq!(
            any_fortran_format(" 31932 Accelerogram points at 100 pts/sec in units of g.   Format: (8f9.6)"),
            Some((8, 9))
        );
        assert_eq!(
            any_fortran_format("13000 points of accel data equally spaced at 0.005 sec, in cm/sec2. (8f10.6)"),
            Some((8, 10))
        );
        assert_eq!(any_fortran_format(" 1138 POINTS OF ACCEL DATA AT  .020 SEC.  (UNITS: CM/SEC/SEC)"), None);
        assert_eq!(fixed_fields("    3   16  36032080 -999", 5), vec!["3", "16", "360", "32080", "-999"]);
        assert_eq!(fortran_tokens("   1.00000-123.45000", Some(10)), vec!["1.00000", "-123.45000"]);
        assert_eq!(fortran_tokens(" 1.5  2.5", Some(10)), vec!["1.5", "2.5"]);
    }
}
