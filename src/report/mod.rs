//! Reports: the data model of an inspection result and its writers
//! (`report.json`, `points.csv`, `report.html`, `junit.xml`).

pub mod csv;
mod decimal;
pub mod html;
pub mod json;
pub mod junit;
mod layout;
mod markup;
pub mod model;
mod plots;
mod profile;
mod svg;
pub mod write;

pub use csv::{points_csv, POINTS_CSV_HEADER};
pub use html::report_html;
pub use json::to_json;
pub use junit::{junit_batch, junit_xml};
pub use model::*;
pub use profile::View;
pub use write::{add_reports, write_reports, REPORT_FILES};
