//! Study output formats: CSV tables (RFC 4180, header row first) and the number formatting and
//! Markdown tables of the reports. A non-finite number is written as an empty CSV cell and as
//! "n/a" in Markdown, never as NaN.

/// One CSV cell.
#[derive(Debug, Clone, PartialEq)]
pub enum Val {
    F(f64),
    I(i64),
    U(u64),
    B(bool),
    S(String),
}

impl From<f64> for Val {
    fn from(v: f64) -> Self {
        Val::F(v)
    }
}
impl From<i64> for Val {
    fn from(v: i64) -> Self {
        Val::I(v)
    }
}
impl From<u64> for Val {
    fn from(v: u64) -> Self {
        Val::U(v)
    }
}
impl From<usize> for Val {
    fn from(v: usize) -> Self {
        Val::U(v as u64)
    }
}
impl From<u32> for Val {
    fn from(v: u32) -> Self {
        Val::U(u64::from(v))
    }
}
impl From<bool> for Val {
    fn from(v: bool) -> Self {
        Val::B(v)
    }
}
impl From<&str> for Val {
    fn from(v: &str) -> Self {
        Val::S(v.to_owned())
    }
}
impl From<String> for Val {
    fn from(v: String) -> Self {
        Val::S(v)
    }
}

impl Val {
    fn csv(&self) -> String {
        match self {
            Val::F(v) if v.is_finite() => format!("{v}"),
            Val::F(_) => String::new(),
            Val::I(v) => v.to_string(),
            Val::U(v) => v.to_string(),
            Val::B(v) => v.to_string(),
            Val::S(s) => {
                if s.contains([',', '"', '\n']) {
                    format!("\"{}\"", s.replace('"', "\"\""))
                } else {
                    s.clone()
                }
            }
        }
    }
}

/// A CSV table built row by row.
#[derive(Debug, Clone, Default)]
pub struct Csv {
    header: Vec<String>,
    rows: Vec<Vec<Val>>,
}

impl Csv {
    pub fn new(header: &[&str]) -> Self {
        Self {
            header: header.iter().map(|s| (*s).to_owned()).collect(),
            rows: Vec::new(),
        }
    }

    pub fn push(&mut self, row: Vec<Val>) {
        self.rows.push(row);
    }

    pub fn len(&self) -> usize {
        self.rows.len()
    }

    pub fn is_empty(&self) -> bool {
        self.rows.is_empty()
    }

    pub fn render(&self) -> String {
        let mut s = self.header.join(",");
        s.push('\n');
        for r in &self.rows {
            let cells: Vec<String> = r.iter().map(Val::csv).collect();
            s.push_str(&cells.join(","));
            s.push('\n');
        }
        s
    }
}

/// `v` with `digits` significant digits, in plain or scientific notation as fits; "n/a" if not finite.
pub fn sig(v: f64, digits: usize) -> String {
    if !v.is_finite() {
        return "n/a".into();
    }
    if v == 0.0 {
        return "0".into();
    }
    let digits = digits.max(1);
    let e = v.abs().log10().floor() as i32;
    if !(-3..6).contains(&e) {
        let s = format!("{:.*e}", digits - 1, v);
        return s;
    }
    let decimals = (digits as i32 - 1 - e).max(0) as usize;
    format!("{v:.decimals$}")
}

/// A ratio as a percentage with `digits` significant digits ("0.12 %").
pub fn pct(v: f64, digits: usize) -> String {
    if !v.is_finite() {
        return "n/a".into();
    }
    format!("{} %", sig(100.0 * v, digits))
}

/// A Markdown table.
pub fn md_table(header: &[&str], rows: &[Vec<String>]) -> String {
    let mut s = format!("| {} |\n", header.join(" | "));
    s.push_str(&format!("|{}\n", "---|".repeat(header.len())));
    for r in rows {
        s.push_str(&format!("| {} |\n", r.join(" | ")));
    }
    s
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn csv_never_writes_nan() {
        let mut c = Csv::new(&["a", "b", "c"]);
        c.push(vec![f64::NAN.into(), 1.5.into(), "x,y".into()]);
        assert_eq!(c.render(), "a,b,c\n,1.5,\"x,y\"\n");
    }

    #[test]
    fn significant_digits() {
        assert_eq!(sig(0.012345, 3), "0.0123");
        assert_eq!(sig(123456.0, 3), "123456");
        assert_eq!(sig(1.234e7, 3), "1.23e7");
        assert_eq!(sig(2.5, 2), "2.5");
        assert_eq!(sig(1e-7, 2), "1.0e-7");
        assert_eq!(sig(f64::INFINITY, 2), "n/a");
        assert_eq!(pct(0.0123, 2), "1.2 %");
    }
}
