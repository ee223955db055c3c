//! How numbers are written in the HTML and text reports. Megabytes are decimal (10⁶ bytes),
//! as bandwidth figures are (seed 004 counts 94 MB/s for 1024×768×2 bytes × 60).

/// Bytes in a megabyte.
pub const BYTES_PER_MEGABYTE: f64 = 1e6;

/// Decimal places that keep a non-zero figure visible: two, or three below 0.01, or four
/// below 0.001. Used for megabytes, millijoules and ratios alike.
fn decimals(value: f64) -> usize {
    let magnitude = value.abs();
    if magnitude == 0.0 || magnitude >= 0.01 {
        2
    } else if magnitude >= 0.001 {
        3
    } else {
        4
    }
}

/// A figure with the decimals of [`decimals`]; `–` for zero, `n/a` when not finite.
pub fn figure(value: f64) -> String {
    if !value.is_finite() {
        "n/a".to_string()
    } else if value == 0.0 {
        "–".to_string()
    } else {
        format!("{value:.*}", decimals(value))
    }
}

/// Bytes as megabytes without the unit: `6.63`; `–` for zero.
pub fn megabytes(bytes: f64) -> String {
    figure(bytes / BYTES_PER_MEGABYTE)
}

/// A count with thousands separators: `828,097`.
pub fn count(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(c);
    }
    out
}

/// A ratio to the first column: `2.45×`.
pub fn ratio(value: f64) -> String {
    if value.is_finite() { format!("{value:.2}×") } else { "n/a".to_string() }
}

/// Bytes in the unit that suits them, for legends: `512 B`, `4.0 KB`, `3.69 MB`.
pub fn bytes_with_unit(bytes: f64) -> String {
    if bytes < 1e3 {
        format!("{bytes:.0} B")
    } else if bytes < 1e6 {
        format!("{:.1} KB", bytes / 1e3)
    } else {
        format!("{:.2} MB", bytes / 1e6)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn figures_keep_small_values_visible() {
        assert_eq!(megabytes(6_630_000.0), "6.63");
        assert_eq!(megabytes(0.0), "–");
        assert_eq!(megabytes(4_096.0), "0.004");
        assert_eq!(megabytes(512.0), "0.0005");
        assert_eq!(megabytes(12_345.0), "0.01");
        assert_eq!(figure(f64::NAN), "n/a");
        assert_eq!(count(828_097), "828,097");
        assert_eq!(count(12), "12");
        assert_eq!(ratio(2.4512), "2.45×");
        assert_eq!(bytes_with_unit(4096.0), "4.1 KB");
    }
}
