//! `points.csv`: every reported point of every feature, one per line.

use super::decimal::push_integer;
use super::markup::{csv_field, push_json_number, TextSink};
use super::model::{PointReport, Report};

/// Header line of `points.csv` (without the line end).
pub const POINTS_CSV_HEADER: &str = "feature,index,x,y,z,nominal_x,nominal_y,nominal_z,\
normal_i,normal_j,normal_k,deviation_mm,true_deviation_mm";

/// Typical bytes of one line of `points.csv` besides the feature name.
const LINE_BYTES: usize = 240;

/// All points in feature order, then point order; `index` counts from 0
/// within the feature; `x,y,z` is the measured point (part coordinates).
/// Numbers are written exactly as in `report.json`, so they round-trip to
/// the same `f64`. Lines end with `\n`.
pub fn points_csv(report: &Report) -> String {
    let mut csv = PointsCsv::new(report);
    for feature in &report.features {
        csv.begin_feature(&feature.name);
        for (index, point) in feature.points.iter().enumerate() {
            csv.begin_line(index);
            push_point_fields(&mut csv.out, point);
            csv.end_line();
        }
    }
    String::from_utf8(csv.into_bytes()).unwrap_or_default()
}

/// `points.csv` being written line by line: the header, then per point
/// its feature, index and numeric fields (given as their text).
#[derive(Debug)]
pub struct PointsCsv {
    out: Vec<u8>,
    /// The current feature's name as a CSV field.
    name: String,
}

impl PointsCsv {
    /// The header line, in a buffer sized for the report's points.
    pub fn new(report: &Report) -> PointsCsv {
        let lines: usize = report.features.iter().map(|f| f.points.len()).sum();
        let mut out = Vec::with_capacity(POINTS_CSV_HEADER.len() + 1 + lines * LINE_BYTES);
        out.extend_from_slice(POINTS_CSV_HEADER.as_bytes());
        out.push(b'\n');
        PointsCsv {
            out,
            name: String::new(),
        }
    }

    /// Starts the points of the feature named `name`.
    pub fn begin_feature(&mut self, name: &str) {
        self.name = csv_field(name);
    }

    /// Starts the line of the feature's point `index`.
    pub fn begin_line(&mut self, index: usize) {
        self.out.extend_from_slice(self.name.as_bytes());
        self.out.push(b',');
        push_integer(&mut self.out, index as u64);
        self.out.push(b',');
    }

    /// The numeric field `k` of the line (counted from 0), as text.
    pub fn field(&mut self, k: usize, text: &[u8]) {
        if k > 0 {
            self.out.push(b',');
        }
        self.out.extend_from_slice(text);
    }

    /// Ends the line.
    pub fn end_line(&mut self) {
        self.out.push(b'\n');
    }

    /// The whole file.
    pub fn into_bytes(self) -> Vec<u8> {
        self.out
    }
}

/// Appends the numeric fields of one point, comma-separated.
fn push_point_fields<S: TextSink + ?Sized>(out: &mut S, point: &PointReport) {
    let numbers = point
        .measured
        .iter()
        .chain(&point.nominal)
        .chain(&point.normal)
        .chain([&point.deviation_mm, &point.true_deviation_mm]);
    for (k, value) in numbers.enumerate() {
        if k > 0 {
            out.push_ascii(b",");
        }
        push_json_number(out, *value);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn point_fields_in_header_order() {
        let point = PointReport {
            measured: [1.0, 2.0, 3.0],
            nominal: [4.0, 5.0, 6.0],
            normal: [0.0, 0.0, 1.0],
            deviation_mm: 0.1,
            true_deviation_mm: -2.5e-7,
            edge: false,
            off_section: false,
            in_section: None,
            measured_in_section: None,
        };
        let mut fields = String::new();
        push_point_fields(&mut fields, &point);
        assert_eq!(fields, "1.0,2.0,3.0,4.0,5.0,6.0,0.0,0.0,1.0,0.1,-2.5e-7");
        assert_eq!(
            fields.split(',').count() + 2,
            POINTS_CSV_HEADER.split(',').count()
        );
    }
}
