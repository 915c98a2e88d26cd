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
mod ryu_like {
    use std::fmt::Write;

    #[derive(Default)]
    pub struct Buf(String);

    impl Buf {
        pub fn format(&mut self, v: f64) -> &str {
            self.0.clear();
            write!(self.0, "{v}").expect("writing to a String");
            &self.0
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use rhonn::experiment::{Recorder, Sample};

    #[test]
    fn header_and_rows() {
        let mut t = Trace::default();
        for k in 0..3 {
            t.record(&Sample {
                t: k as f64 * 1e-3,
                p_line: 2e6,
                stroke: 1.5e-3,
                current: 0.25,
                demand: 0.0,
                p_ref: None,
                p_meas: None,
                hat: [None, None],
                hat_parallel: [None, None],
                control: None,
                baseline: None,
                second_baseline: None,
            });
        }
        let mut out = Vec::new();
        write_trace_csv(&mut out, &t).unwrap();
        let s = String::from_utf8(out).unwrap();
        let lines: Vec<&str> = s.lines().collect();
        assert_eq!(lines[0], "t,p_line,stroke,current,demand");
        assert_eq!(lines[2], "0.001,2000000,0.0015,0.25,0");
        assert_eq!(lines.len(), 4);
    }
}
