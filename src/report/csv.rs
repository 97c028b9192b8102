//! `points.csv`: every reported point of every feature, one per line.

use super::markup::{csv_field, json_number};
use super::model::{PointReport, Report};

/// Header line of `points.csv` (without the line end).
pub const POINTS_CSV_HEADER: &str = "feature,index,x,y,z,nominal_x,nominal_y,nominal_z,\
normal_i,normal_j,normal_k,deviation_mm,true_deviation_mm";

/// All points in feature order, then point order; `index` counts from 0
/// within the feature; `x,y,z` is the measured point (part coordinates).
/// Numbers are written exactly as in `report.json`, so they round-trip to
/// the same `f64`. Lines end with `\n`.
pub fn points_csv(report: &Report) -> String {
    let mut out = String::from(POINTS_CSV_HEADER);
    out.push('\n');
    for feature in &report.features {
        let name = csv_field(&feature.name);
        for (index, point) in feature.points.iter().enumerate() {
            out.push_str(&format!("{name},{index},{}\n", point_fields(point)));
        }
    }
    out
}

/// The numeric fields of one point, comma-separated.
fn point_fields(point: &PointReport) -> String {
    let numbers = point
        .measured
        .iter()
        .chain(&point.nominal)
        .chain(&point.normal)
        .chain([&point.deviation_mm, &point.true_deviation_mm]);
    numbers
        .map(|v| json_number(*v))
        .collect::<Vec<_>>()
        .join(",")
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
        };
        let fields = point_fields(&point);
        assert_eq!(fields, "1.0,2.0,3.0,4.0,5.0,6.0,0.0,0.0,1.0,0.1,-2.5e-7");
        assert_eq!(
            fields.split(',').count() + 2,
            POINTS_CSV_HEADER.split(',').count()
        );
    }
}
