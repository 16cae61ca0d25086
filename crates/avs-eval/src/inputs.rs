//! Input files: read from disk, or the shipped defaults (the office environment, its knowledge,
//! the object-search domain) embedded in the program, so that a program built from avs finds
//! them wherever it runs — no checkout beside it, no path compiled in.
//!
//! ```
//! use avs_eval::inputs::{Input, Shipped};
//! let knowledge = Shipped::Knowledge.input().knowledge().unwrap();
//! assert!(knowledge.class("cerealbox").is_some());
//! // A path given by the user wins over the default.
//! let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
//! let domain = Input::or_shipped(Some(&root.join("domains/object_search.yaml")), Shipped::Domain)
//!     .unwrap()
//!     .domain()
//!     .unwrap();
//! assert!(!domain.operators.is_empty());
//! ```

use crate::edits::{edit_environment, EditField, WorldEdits};
use crate::EvalError;
use avs_format::knowledge::Knowledge;
use avs_plan::domain::Domain;
use avs_sim::World;
use std::path::{Path, PathBuf};

/// A shipped default input.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Shipped {
    /// The default world: `domains/environments/office.yaml`.
    Environment,
    /// The office knowledge: `knowledge/office.yaml`.
    Knowledge,
    /// The object-search planning domain: `domains/object_search.yaml`.
    Domain,
}

impl Shipped {
    /// Its path in a checkout of avs.
    pub const fn path(self) -> &'static str {
        match self {
            Shipped::Environment => "domains/environments/office.yaml",
            Shipped::Knowledge => "knowledge/office.yaml",
            Shipped::Domain => "domains/object_search.yaml",
        }
    }

    /// Its text, as embedded when the program was built.
    pub const fn text(self) -> &'static str {
        match self {
            Shipped::Environment => {
                include_str!("../../../domains/environments/office.yaml")
            }
            Shipped::Knowledge => include_str!("../../../knowledge/office.yaml"),
            Shipped::Domain => include_str!("../../../domains/object_search.yaml"),
        }
    }

    /// The input: the checkout's file when the current directory is a checkout that has it (so
    /// edits there take effect), else the embedded text.
    pub fn input(self) -> Input {
        let here = Path::new(self.path());
        match here.is_file().then(|| Input::read(here)) {
            Some(Ok(input)) => input,
            _ => Input {
                name: format!("{} (built in)", self.path()),
                text: self.text().to_string(),
                base_dir: PathBuf::from("."),
            },
        }
    }
}

/// An input file's text, with the name messages use and the folder its relative paths (a map
/// image) resolve against.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Input {
    /// The file's name in messages (its path, or a shipped default's).
    pub name: String,
    /// Its text.
    pub text: String,
    /// The folder relative paths inside it resolve against.
    pub base_dir: PathBuf,
}

impl Input {
    /// Read the file at `path` (with the readers' size bound).
    pub fn read(path: &Path) -> Result<Input, EvalError> {
        let name = path.display().to_string();
        let text = avs_format::read_text(path)?;
        Ok(Input {
            name,
            text,
            base_dir: path.parent().unwrap_or(Path::new(".")).to_path_buf(),
        })
    }

    /// The file at `path` when given, else the shipped default `default`.
    pub fn or_shipped(path: Option<&Path>, default: Shipped) -> Result<Input, EvalError> {
        match path {
            Some(p) => Input::read(p),
            None => Ok(default.input()),
        }
    }

    /// The input as a knowledge file.
    pub fn knowledge(&self) -> Result<Knowledge, EvalError> {
        Ok(avs_format::load_yaml_str(&self.name, &self.text)?)
    }

    /// The input as a planning domain; the error lists every problem.
    pub fn domain(&self) -> Result<Domain, EvalError> {
        Domain::from_yaml(&self.name, &self.text)
            .map_err(|diagnostics| EvalError::Input(avs_format::LoadError { diagnostics }))
    }

    /// The input as an environment, checked as `avs validate` checks it (its class names too,
    /// against `knowledge` when given), with `edits` applied, built into its world; errors
    /// name the file and the edit (`describe` turns an [`EditField`] into the caller's name for
    /// it, e.g. a flag).
    pub fn edited_world(
        &self,
        knowledge: Option<&Knowledge>,
        edits: &WorldEdits,
        describe: impl Fn(EditField) -> String,
    ) -> Result<World, EvalError> {
        let file = &self.name;
        // The file as written gets `avs validate`'s checks with lines and columns; the edited
        // environment gets them again when its world is built.
        let mut env = World::read_checked_text(file, &self.text, &self.base_dir, knowledge)
            .map_err(|e| EvalError::environment(file, e))?;
        edit_environment(&mut env, edits, file).map_err(|(which, message)| EvalError::Field {
            file: file.clone(),
            field: describe(which),
            message,
        })?;
        World::named(file, env, &self.base_dir).map_err(|e| EvalError::environment(file, e))
    }

    /// The input as an environment built into its world, checked as `avs validate` checks it.
    pub fn world(&self) -> Result<World, EvalError> {
        self.edited_world(None, &WorldEdits::default(), |_| String::new())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_built_in_defaults_load_and_name_themselves_as_built_in() {
        for s in [Shipped::Environment, Shipped::Knowledge, Shipped::Domain] {
            let built_in = Input {
                name: format!("{} (built in)", s.path()),
                text: s.text().to_string(),
                base_dir: PathBuf::from("."),
            };
            match s {
                Shipped::Environment => drop(built_in.world().unwrap()),
                Shipped::Knowledge => drop(built_in.knowledge().unwrap()),
                Shipped::Domain => drop(built_in.domain().unwrap()),
            }
        }
        // An error in embedded text names it as built in.
        let bad = Input {
            name: "knowledge/office.yaml (built in)".into(),
            text: "kind: knowledge\nnot_a_field: 1\n".into(),
            base_dir: PathBuf::from("."),
        };
        let e = bad.knowledge().unwrap_err().to_string();
        assert!(e.contains("knowledge/office.yaml (built in)"), "{e}");
    }

    #[test]
    fn a_missing_file_is_an_error_naming_it() {
        let e = Input::read(Path::new("/nonexistent/k.yaml"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("/nonexistent/k.yaml"), "{e}");
    }
}
