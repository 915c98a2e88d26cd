//! Trajectories as CSV: a header of column names, then one row per sample, SI units.

use rhonn::experiment::Trace;
use std::io::Write;

/// Write `trace` as CSV (header `t,p_line,stroke,...`; values in SI, shortest
/// round-trip decimal form).
pub fn write_trace_csv(w: &mut dyn Write, trace: &Trace) -> std::io::Result<()> {
    let mut wr = csv::Writer::from_writer(w);
    wr.write_record(trace.columns.iter().map(|c| c.name.as_str()))
        .map_err(std::io::Error::other)?;
    let mut buf = ryu_like::Buf::default();
    for k in 0..trace.len() {
        for c in &trace.columns {
            wr.write_field(buf.format(c.values[k]))
                .map_err(std::io::Error::other)?;
        }
        wr.write_record(None::<&[u8]>).map_err(std::io::Error::other)?;
    }
    wr.flush()
}

/// Formatting of floats without a per-value allocation.
pub(crate) mod ryu_like {
    use std::fmt::Write;

    #[derive(Default)]
    pub struct Buf(String);

    impl Buf {
        /// The shortest decimal that reads back as `v`: plain within [1e-5, 1e16), with an
        /// exponent outside (`{v}` writes 1e-310 in 312 characters).
        pub fn format(&mut self, v: f64) -> &str {
            self.0.clear();
            let a = v.abs();
            if a == 0.0 || !a.is_finite() || (1e-5..1e16).contains(&a) {
                write!(self.0, "{v}")
            } else {
                write!(self.0, "{v:e}")
            }
            .expect("writing to a String");
            &self.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rhonn::experiment::Column;

    #[test]
    fn header_and_rows() {
        let col = |name: &str, unit, v: f64| Column {
            name: name.into(),
            unit,
            values: vec![v; 3],
        };
        let mut t = Trace {
            columns: vec![
                col("t", "s", 0.0),
                col("p_line", "Pa", 2e6),
                col("stroke", "m", 1.5e-3),
                col("current", "A", 0.25),
                col("demand", "m^3/s", 0.0),
            ],
        };
        t.columns[0].values = (0..3).map(|k| k as f64 * 1e-3).collect();
        let mut out = Vec::new();
        write_trace_csv(&mut out, &t).unwrap();
        let s = String::from_utf8(out).unwrap();
        let lines: Vec<&str> = s.lines().collect();
        assert_eq!(lines[0], "t,p_line,stroke,current,demand");
        assert_eq!(lines[2], "0.001,2000000,0.0015,0.25,0");
        assert_eq!(lines.len(), 4);
    }

    #[test]
    fn every_value_is_written_in_its_shortest_form_and_reads_back_exactly() {
        let mut b = ryu_like::Buf::default();
        for (v, text) in [
            (1e-310, "1e-310"),
            (-2.5e-7, "-2.5e-7"),
            (0.1, "0.1"),
            (1e-5, "0.00001"),
            (123456.75, "123456.75"),
            (1e20, "1e20"),
            (0.0, "0"),
        ] {
            assert_eq!(b.format(v), text);
            assert_eq!(b.format(v).parse::<f64>().unwrap(), v);
        }
        let mut x = 1.234_567_890_123e-300;
        while x < 1e300 {
            assert_eq!(b.format(x).parse::<f64>().unwrap(), x);
            assert!(b.format(x).len() <= 24, "{}", b.format(x));
            x *= 7.77;
        }
    }
}
