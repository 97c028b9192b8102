//! Corrections learned across parts (`--corrections FILE`,
//! `cmm-corrections/1`): parts made on the same machine tool from the same
//! design usually repeat their deviation, so the next part starts from the
//! corrected design data and scans without trajectory errors.
use std::path::{Path, PathBuf};

use serde::{Deserialize, Serialize};

use super::{Learned, LearnedSet};

/// Format tag of corrections files.
pub const CORRECTIONS_FORMAT: &str = "cmm-corrections/1";

/// One stored correction.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Entry {
    /// Program name.
    pub program: String,
    /// Feature name.
    pub feature: String,
    /// Index of the section curve within the feature.
    pub curve: usize,
    /// The correction.
    pub correction: Learned,
}

/// A corrections file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CorrectionsFile {
    /// Always [`CORRECTIONS_FORMAT`].
    pub format: String,
    /// Entries, later ones replacing earlier ones with the same key.
    pub entries: Vec<Entry>,
}

/// Why a corrections file could not be read.
#[derive(Debug, thiserror::Error)]
pub enum CorrectionsError {
    /// Unreadable.
    #[error("{file}: cannot read: {source}")]
    Io {
        /// The file.
        file: PathBuf,
        /// The reason.
        source: std::io::Error,
    },
    /// Not valid JSON, or a value of the wrong type or an unknown key.
    #[error(transparent)]
    Syntax(#[from] crate::jsonfile::JsonSyntaxError),
    /// Wrong format tag.
    #[error("{file}: $.format: unknown format '{found}', expected '{CORRECTIONS_FORMAT}'")]
    Format {
        /// The file.
        file: PathBuf,
        /// The tag found.
        found: String,
    },
}

impl CorrectionsFile {
    /// An empty set.
    pub fn empty() -> CorrectionsFile {
        CorrectionsFile {
            format: CORRECTIONS_FORMAT.into(),
            entries: Vec::new(),
        }
    }

    /// Reads a file; a missing file is an empty set (the first part).
    pub fn read(path: &Path) -> Result<CorrectionsFile, CorrectionsError> {
        if !path.exists() {
            return Ok(CorrectionsFile::empty());
        }
        let text = crate::jsonfile::read_text(path).map_err(|source| CorrectionsError::Io {
            file: path.to_path_buf(),
            source,
        })?;
        let file: CorrectionsFile = crate::jsonfile::parse_json(&text, path)?;
        if file.format != CORRECTIONS_FORMAT {
            return Err(CorrectionsError::Format {
                file: path.to_path_buf(),
                found: file.format,
            });
        }
        Ok(file)
    }

    /// The corrections known for `program`.
    pub fn for_program(&self, program: &str) -> LearnedSet {
        let mut out: LearnedSet = Vec::new();
        for e in self.entries.iter().filter(|e| e.program == program) {
            let key = (e.feature.clone(), e.curve);
            out.retain(|(k, _)| *k != key);
            out.push((key, e.correction.clone()));
        }
        out
    }

    /// Adds (or replaces) what a run of `program` learned.
    pub fn merge(&mut self, program: &str, learned: &LearnedSet) {
        for ((feature, curve), correction) in learned {
            self.entries
                .retain(|e| !(e.program == program && &e.feature == feature && e.curve == *curve));
            self.entries.push(Entry {
                program: program.into(),
                feature: feature.clone(),
                curve: *curve,
                correction: correction.clone(),
            });
        }
    }

    /// Pretty JSON with a final newline.
    pub fn to_json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self).unwrap_or_default();
        s.push('\n');
        s
    }
}
