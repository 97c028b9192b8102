//! Errors of the CAD reader: every variant names the file and a place in it.
use thiserror::Error;

/// An error while reading a STEP or IGES file.
///
/// `line` and `column` are 1-based; for IGES `line` is the physical line
/// (record) number and `column` the column 1..=80 within it.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum CadError {
    /// The file could not be read at all.
    #[error("{file}:{line}:{column}: cannot read file: {reason}")]
    Io {
        /// File name.
        file: String,
        /// Always 0 (no place in the file).
        line: usize,
        /// Always 0.
        column: usize,
        /// Operating-system message.
        reason: String,
    },
    /// The file extension is not one of .step/.stp/.iges/.igs.
    #[error("{file}:{line}:{column}: unsupported CAD file type: {reason}")]
    UnsupportedType {
        /// File name.
        file: String,
        /// Always 0.
        line: usize,
        /// Always 0.
        column: usize,
        /// What was found.
        reason: String,
    },
    /// Lexical or syntactic error (also truncated files).
    #[error("{file}:{line}:{column}: syntax error: {reason}")]
    Syntax {
        /// File name.
        file: String,
        /// Line of the offending character.
        line: usize,
        /// Column of the offending character.
        column: usize,
        /// What is wrong.
        reason: String,
    },
    /// An entity references an instance that is not defined.
    #[error("{file}:{line}:{column}: #{entity} references #{target}, which is not defined")]
    UnknownReference {
        /// File name.
        file: String,
        /// Line of the referencing entity.
        line: usize,
        /// Column of the referencing entity.
        column: usize,
        /// The referencing entity.
        entity: u64,
        /// The missing instance.
        target: u64,
    },
    /// Instances reference each other in a cycle.
    #[error(
        "{file}:{line}:{column}: cyclic reference: #{entity} refers back to itself ({reason})"
    )]
    CyclicReference {
        /// File name.
        file: String,
        /// Line of an entity on the cycle.
        line: usize,
        /// Column of that entity.
        column: usize,
        /// The entity on the cycle.
        entity: u64,
        /// The cycle as `#a -> #b -> #a`.
        reason: String,
    },
    /// No length unit could be found for the geometry.
    #[error("{file}:{line}:{column}: missing units: {reason}")]
    MissingUnits {
        /// File name.
        file: String,
        /// Line where the unit was looked for.
        line: usize,
        /// Column where the unit was looked for.
        column: usize,
        /// Details.
        reason: String,
    },
    /// An entity has the wrong shape (parameter count, type, value).
    #[error("{file}:{line}:{column}: #{entity}: {reason}")]
    Entity {
        /// File name.
        file: String,
        /// Line of the entity.
        line: usize,
        /// Column of the entity.
        column: usize,
        /// Entity id (STEP instance number or IGES directory sequence number).
        entity: u64,
        /// What is wrong.
        reason: String,
    },
    /// A coordinate or length is not finite or beyond [`MAX_COORDINATE_MM`].
    #[error("{file}:{line}:{column}: #{entity} {entity_type}: {what} {value:e} mm is not finite or beyond {limit:e} mm")]
    OutOfRange {
        /// File name.
        file: String,
        /// Line of the entity.
        line: usize,
        /// Column of the entity.
        column: usize,
        /// Entity id.
        entity: u64,
        /// Entity type (`CARTESIAN_POINT`, ...).
        entity_type: String,
        /// Which value (`coordinate 2`, `radius`).
        what: String,
        /// The value, mm.
        value: f64,
        /// The limit, mm.
        limit: f64,
    },
    /// The file holds no face that could be converted.
    #[error("{file}:{line}:{column}: no usable face: {reason}")]
    NoFaces {
        /// File name.
        file: String,
        /// Line of the data section.
        line: usize,
        /// Column of the data section.
        column: usize,
        /// Why (and how many faces were skipped).
        reason: String,
    },
}

/// Largest coordinate magnitude accepted, mm (1000 km): beyond it a value
/// is taken as corrupt, and products of such values would overflow.
pub const MAX_COORDINATE_MM: f64 = 1e9;

/// Result alias of the CAD reader.
pub type CadResult<T> = Result<T, CadError>;
