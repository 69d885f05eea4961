//! How the report writes its numbers: percentages, counts, sizes, ratios and the names of
//! tables and evaluator units, shared by REPORT.md's sections and its summary and pick.

use crate::evaluator::EvaluatorUnit;
use crate::table::Layout;

/// A relative error as a percentage, with more decimals the smaller it is.
pub(crate) fn pct(x: f64) -> String {
    if !x.is_finite() {
        "–".into()
    } else if x >= 0.1 {
        format!("{:.1}%", 100.0 * x)
    } else if x >= 0.001 {
        format!("{:.2}%", 100.0 * x)
    } else {
        format!("{:.3}%", 100.0 * x)
    }
}

/// A number with thousands separators, no decimals (or two below 10).
pub(crate) fn num(x: f64) -> String {
    if !x.is_finite() {
        return "–".into();
    }
    if x.abs() < 10.0 {
        return format!("{x:.2}");
    }
    let digits = format!("{:.0}", x.abs());
    let mut out = String::new();
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i) % 3 == 0 {
            out.push(',');
        }
        out.push(c);
    }
    if x < 0.0 { format!("-{out}") } else { out }
}

/// Bytes in KiB or MiB.
pub(crate) fn size(bytes: usize) -> String {
    let kib = bytes as f64 / 1024.0;
    if kib < 1024.0 {
        format!("{kib:.0} KiB")
    } else {
        format!("{:.1} MiB", kib / 1024.0)
    }
}

/// A table as the report names it: "thread_frame 48".
pub(crate) fn table_name(layout: Layout, resolution: u32) -> String {
    format!("{layout} {resolution}")
}

/// What a cell says where no point of the baseline is as accurate.
pub(crate) const NONE_UP_TO_THE_LARGEST: &str = "none up to the largest setting";

/// The baseline unit's name, as the report's prose names it.
pub(crate) fn baseline_name() -> &'static str {
    super::baseline_unit().map_or("the baseline", |unit| unit.name)
}

/// Units' names as a list in prose: "a", "a and b", "a, b and c".
pub(crate) fn unit_names(units: &[&EvaluatorUnit]) -> String {
    let names: Vec<&str> = units.iter().map(|unit| unit.name).collect();
    match names.split_last() {
        None => "none".into(),
        Some((last, [])) => last.to_string(),
        Some((last, rest)) => format!("{} and {last}", rest.join(", ")),
    }
}

/// The heading of a unit's section in REPORT.md.
pub(crate) fn unit_heading(unit: &EvaluatorUnit) -> String {
    format!("The {} evaluator", unit.name)
}

/// The GitHub anchor of [`unit_heading`]: lower case, spaces as hyphens, and no
/// punctuation but hyphens and underscores.
pub(crate) fn unit_anchor(unit: &EvaluatorUnit) -> String {
    unit_heading(unit)
        .to_lowercase()
        .chars()
        .filter_map(|c| match c {
            ' ' => Some('-'),
            c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
            _ => None,
        })
        .collect()
}

/// A ratio as "12×" or "1.25×"; "–" when missing.
pub(crate) fn ratio(x: Option<f64>) -> String {
    x.map_or("–".into(), |r| {
        if r >= 10.0 {
            format!("{r:.0}×")
        } else {
            format!("{r:.2}×")
        }
    })
}

#[cfg(test)]
mod tests {
    use super::{num, pct};

    #[test]
    fn number_formats() {
        assert_eq!(num(1234567.4), "1,234,567");
        assert_eq!(num(123.4), "123");
        assert_eq!(num(1.234), "1.23");
        assert_eq!(pct(0.0123), "1.23%");
        assert_eq!(pct(0.25), "25.0%");
    }
}
