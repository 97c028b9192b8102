//! `points.csv`: every reported point of every feature, one per line.

use std::fmt::Write;

use super::markup::{csv_field, push_json_number};
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
    let lines: usize = report.features.iter().map(|f| f.points.len()).sum();
    let mut out = String::with_capacity(POINTS_CSV_HEADER.len() + 1 + lines * LINE_BYTES);
    out.push_str(POINTS_CSV_HEADER);
    out.push('\n');
    for feature in &report.features {
        let name = csv_field(&feature.name);
        for (index, point) in feature.points.iter().enumerate() {
            out.push_str(&name);
            out.push(',');
            // Writing into a String cannot fail.
            let _ = write!(out, "{index}");
            out.push(',');
            push_point_fields(&mut out, point);
            out.push('\n');
        }
    }
    out
}

/// Appends the numeric fields of one point, comma-separated.
fn push_point_fields(out: &mut String, point: &PointReport) {
    let numbers = point
        .measured
        .iter()
        .chain(&point.nominal)
        .chain(&point.normal)
        .chain([&point.deviation_mm, &point.true_deviation_mm]);
    for (k, value) in numbers.enumerate() {
        if k > 0 {
            out.push(',');
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
