//! The CSV of a run as FMPy's `write_csv` writes it: a header of quoted names, then rows
//! of Python-formatted numbers ([`python_float_repr`]), integers and `True`/`False`.

use super::{SimulationResult, Value};
use std::io::{self, Write};

impl SimulationResult {
    /// Write the result as FMPy's `write_csv` does.
    pub fn write_csv(&self, out: &mut impl Write) -> io::Result<()> {
        write_header(out, &self.columns)?;
        for (time, values) in &self.rows {
            write_row(out, *time, values)?;
        }
        Ok(())
    }
}

pub(super) fn write_header(out: &mut (impl Write + ?Sized), columns: &[String]) -> io::Result<()> {
    let header: Vec<String> = columns.iter().map(|c| format!("\"{c}\"")).collect();
    writeln!(out, "{}", header.join(","))
}

pub(super) fn write_row(
    out: &mut (impl Write + ?Sized),
    time: f64,
    values: &[Value],
) -> io::Result<()> {
    let mut line = python_float_repr(time);
    for v in values {
        line.push(',');
        match v {
            Value::Real(x) => line.push_str(&python_float_repr(*x)),
            Value::Integer(i) => line.push_str(&i.to_string()),
            Value::Boolean(b) => line.push_str(if *b { "True" } else { "False" }),
        }
    }
    writeln!(out, "{line}")
}

/// Python's `repr(float)` (which numpy's `str(float64)` matches): the shortest digits
/// that read back to the same value, positional for decimal exponents −4 ≤ e < 16 (always
/// with a fractional part), scientific otherwise with a signed exponent of at least two
/// digits (`1e-05`, `1.5e+16`), and `nan`, `inf`, `-inf`.
pub fn python_float_repr(x: f64) -> String {
    if x.is_nan() {
        return "nan".into();
    }
    if x.is_infinite() {
        return if x > 0.0 { "inf".into() } else { "-inf".into() };
    }
    if x == 0.0 {
        return if x.is_sign_negative() {
            "-0.0".into()
        } else {
            "0.0".into()
        };
    }
    // Rust's `{:e}` gives the shortest round-trip digits: "-1.2345e-5".
    let sci = format!("{x:e}");
    let (mantissa, exponent) = sci.split_once('e').expect("LowerExp has an exponent");
    let exponent: i32 = exponent.parse().expect("LowerExp exponent is an integer");
    let negative = mantissa.starts_with('-');
    let digits: String = mantissa.chars().filter(|c| c.is_ascii_digit()).collect();
    let mut out = String::new();
    if negative {
        out.push('-');
    }
    if !(-4..16).contains(&exponent) {
        out.push_str(&digits[..1]);
        if digits.len() > 1 {
            out.push('.');
            out.push_str(&digits[1..]);
        }
        out.push_str(&format!(
            "e{}{:02}",
            if exponent < 0 { '-' } else { '+' },
            exponent.abs()
        ));
    } else if exponent >= 0 {
        let int_len = exponent as usize + 1;
        if digits.len() <= int_len {
            out.push_str(&digits);
            out.push_str(&"0".repeat(int_len - digits.len()));
            out.push_str(".0");
        } else {
            out.push_str(&digits[..int_len]);
            out.push('.');
            out.push_str(&digits[int_len..]);
        }
    } else {
        out.push_str("0.");
        out.push_str(&"0".repeat((-exponent - 1) as usize));
        out.push_str(&digits);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simulate::RunEnd;

    #[test]
    fn float_repr_matches_python() {
        // expected strings produced by Python's repr() / numpy's str()
        let cases: [(f64, &str); 22] = [
            (0.0, "0.0"),
            (-0.0, "-0.0"),
            (1.0, "1.0"),
            (0.1, "0.1"),
            (1e-5, "1e-05"),
            (0.0001, "0.0001"),
            (123456789012345.6, "123456789012345.6"),
            (1e15, "1000000000000000.0"),
            (1e16, "1e+16"),
            (1.5e16, "1.5e+16"),
            (-2.5e-7, "-2.5e-07"),
            (1e100, "1e+100"),
            (1.7976931348623157e308, "1.7976931348623157e+308"),
            (5e-324, "5e-324"),
            (0.30000000000000004, "0.30000000000000004"),
            (100.0, "100.0"),
            (2.0 / 3.0, "0.6666666666666666"),
            (1e22, "1e+22"),
            (12345.678, "12345.678"),
            (-1e-4, "-0.0001"),
            (f64::NAN, "nan"),
            (f64::NEG_INFINITY, "-inf"),
        ];
        for (x, expected) in cases {
            assert_eq!(python_float_repr(x), expected, "{x:e}");
        }
    }

    #[test]
    fn csv_layout() {
        let result = SimulationResult {
            columns: vec!["time".into(), "x".into(), "n".into(), "b".into()],
            rows: vec![
                (
                    0.0,
                    vec![Value::Real(1.0), Value::Integer(0), Value::Boolean(false)],
                ),
                (
                    0.01,
                    vec![
                        Value::Real(-2.5e-7),
                        Value::Integer(-3),
                        Value::Boolean(true),
                    ],
                ),
            ],
            end: RunEnd::Completed,
        };
        let mut out = Vec::new();
        result.write_csv(&mut out).unwrap();
        assert_eq!(
            String::from_utf8(out).unwrap(),
            "\"time\",\"x\",\"n\",\"b\"\n0.0,1.0,0,False\n0.01,-2.5e-07,-3,True\n"
        );
    }
}
