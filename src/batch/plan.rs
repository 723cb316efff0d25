//! The plan file (`*.plan.ron`): which faces, which states, views, styles, sizes and outputs
//! a batch renders. Parsed with errors that name the file, line and column; the states it
//! names are checked against each face's table when the plan is expanded ([`super::items`]).

use std::path::{Path, PathBuf};

use serde::Deserialize;

use crate::facs::combo::{letter_factor, parse_combo, Combo};
use crate::facs::AuKey;
use crate::io::error::{read_text, LoadError, MAX_FILE_BYTES};
use crate::io::ron_text;
use crate::render::Style;

/// The plan format version this build reads.
pub const PLAN_VERSION: u32 = 1;

/// The largest image side a plan may ask for (as `render` accepts).
pub const MAX_IMAGE_SIDE: u32 = crate::render::png::MAX_SIDE as u32;

/// The largest text size (columns or rows) a plan may ask for.
pub const MAX_TEXT_SIDE: u32 = 2000;

/// A parsed plan file, as written (see docs/formats.md, "Batch plans").
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields, rename = "plan")]
pub struct PlanFile {
    /// File format version; see [`PLAN_VERSION`].
    pub version: u32,
    /// The faces, each a rig with its AU table.
    pub faces: Vec<FaceSpec>,
    /// What to show on every face.
    pub show: Vec<Show>,
    /// FACS intensity letters (A-E) applied to the AUs of `Aus`, `AllAus`, `Pairs` and
    /// `Triples`; none: each AU as recorded.
    #[serde(default)]
    pub intensities: Vec<String>,
    /// The views of image and text outputs; none: the front view.
    #[serde(default)]
    pub views: Vec<ViewSpec>,
    /// The drawing styles of image and text outputs; none: shaded.
    #[serde(default)]
    pub styles: Vec<StyleName>,
    /// Image size in pixels (PNG, SVG); default 256x256.
    #[serde(default = "default_size")]
    pub size: (u32, u32),
    /// Text size in columns and rows; default 80x36.
    #[serde(default = "default_text_size")]
    pub text_size: (u32, u32),
    /// The files made for every state.
    pub outputs: Vec<Output>,
}

fn default_size() -> (u32, u32) {
    (256, 256)
}

fn default_text_size() -> (u32, u32) {
    (80, 36)
}

/// One face of a plan.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FaceSpec {
    /// The face's name in labels and file paths (letters, digits, `-` and `_`).
    pub name: String,
    /// The rig: `builtin:default`, `builtin:paper` or a file (relative to the plan's folder).
    pub rig: PathBuf,
    /// The AU table (relative to the plan's folder, or `builtin:default`); left out: the
    /// built-in table, when the rig has its muscles.
    #[serde(default)]
    pub table: PathBuf,
}

/// What to show: one entry of `show`, expanded into states.
#[derive(Debug, Clone, Deserialize)]
pub enum Show {
    /// The rest face.
    Neutral,
    /// Every AU the face's table records, one at a time.
    AllAus,
    /// These AUs, one at a time (`"12"`, `"L12"`).
    Aus(Vec<String>),
    /// Combinations as FACS writes them (`"1+2+5B+26"`), as given (not scaled by
    /// `intensities`).
    Combos(Vec<String>),
    /// Every named expression of the face's table.
    AllExpressions,
    /// These named expressions of the face's table.
    Expressions(Vec<String>),
    /// Every pair of these AUs.
    Pairs(Vec<String>),
    /// Every triple of these AUs.
    Triples(Vec<String>),
    /// Combinations drawn at random (reproducibly, from the seed); see [`RandomSpec`].
    Random {
        /// How many combinations.
        count: u32,
        /// The seed.
        seed: u64,
        /// The AUs to draw from.
        aus: Vec<String>,
        /// The least and most AUs in a combination (default 2 to 3).
        #[serde(default = "default_terms")]
        terms: (u32, u32),
        /// The intensity letters to draw from (default `"ABCDE"`).
        #[serde(default = "default_letters")]
        letters: String,
    },
}

impl Show {
    /// The `Random` entry's fields.
    pub fn random(&self) -> Option<RandomSpec> {
        match self {
            Show::Random {
                count,
                seed,
                aus,
                terms,
                letters,
            } => Some(RandomSpec {
                count: *count,
                seed: *seed,
                aus: aus.clone(),
                terms: *terms,
                letters: letters.clone(),
            }),
            _ => None,
        }
    }
}

/// `Random(...)`: `count` distinct combinations of `terms` AUs drawn from `aus`, each AU at
/// a letter drawn from `letters`.
#[derive(Debug, Clone, Default)]
pub struct RandomSpec {
    /// How many combinations.
    pub count: u32,
    /// The seed: the same seed draws the same combinations on every machine.
    pub seed: u64,
    /// The AUs to draw from.
    pub aus: Vec<String>,
    /// The least and most AUs in a combination (default 2 to 3).
    pub terms: (u32, u32),
    /// The intensity letters to draw from (default `"ABCDE"`).
    pub letters: String,
}

fn default_terms() -> (u32, u32) {
    (2, 3)
}

fn default_letters() -> String {
    "ABCDE".to_string()
}

/// A view: degrees of yaw (positive shows the subject's left cheek) and pitch (positive
/// looks down from above).
#[derive(Debug, Clone, Copy, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ViewSpec {
    /// Degrees of turn.
    #[serde(default)]
    pub yaw: f32,
    /// Degrees of tilt.
    #[serde(default)]
    pub pitch: f32,
}

/// A drawing style as a plan names it.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
pub enum StyleName {
    /// Feature lines.
    Lines,
    /// The lit surface.
    Shaded,
    /// Every visible edge.
    Wireframe,
}

impl StyleName {
    /// The renderer's style.
    pub fn style(self) -> Style {
        match self {
            StyleName::Lines => Style::Lines,
            StyleName::Shaded => Style::Shaded,
            StyleName::Wireframe => Style::Wireframe,
        }
    }
}

/// An output file format.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Deserialize)]
pub enum Output {
    /// PNG image (size, view, style).
    Png,
    /// SVG image (size, view, style).
    Svg,
    /// Braille text (text size, view, style).
    Txt,
    /// The deformed mesh as Wavefront OBJ (one per state: no view or style).
    Obj,
    /// The deformed mesh as binary glTF (one per state).
    Glb,
}

impl Output {
    /// The file extension and the name in labels.
    pub fn ext(self) -> &'static str {
        match self {
            Output::Png => "png",
            Output::Svg => "svg",
            Output::Txt => "txt",
            Output::Obj => "obj",
            Output::Glb => "glb",
        }
    }

    /// Whether the output is a picture (drawn from a view in a style).
    pub fn is_picture(self) -> bool {
        matches!(self, Output::Png | Output::Svg | Output::Txt)
    }
}

/// A plan read from a file, with its text kept for error positions and the plan hash.
#[derive(Debug, Clone)]
pub struct Plan {
    /// The plan file.
    pub path: PathBuf,
    /// Its text.
    pub text: String,
    /// The parsed plan.
    pub file: PlanFile,
}

impl Plan {
    /// Reads and checks a plan file.
    pub fn load(path: &Path) -> Result<Plan, LoadError> {
        let text = read_text(path, MAX_FILE_BYTES)?;
        Plan::parse(path, text)
    }

    /// Parses and checks plan text read from `path`.
    pub fn parse(path: &Path, text: String) -> Result<Plan, LoadError> {
        ron_text::check_version(path, &text, PLAN_VERSION, "plan")?;
        let file: PlanFile = ron_text::parse(path, &text, "a batch plan")?;
        let plan = Plan {
            path: path.to_path_buf(),
            text,
            file,
        };
        plan.check()?;
        Ok(plan)
    }

    /// An error at the first `"literal"` after the field `field`, or at the field.
    pub fn error_at(&self, field: &str, literal: &str, message: impl Into<String>) -> LoadError {
        let field_at = ron_text::find_field(&self.text, 0, field);
        let at = ron_text::find_string(&self.text, field_at.unwrap_or(0), literal).or(field_at);
        match at {
            Some(offset) => LoadError::at_offset(&self.path, &self.text, offset, message),
            None => LoadError::new(&self.path, message),
        }
    }

    /// An error at a field (or about the whole file when it is not written).
    pub fn field_error(&self, field: &str, message: impl Into<String>) -> LoadError {
        match ron_text::find_field(&self.text, 0, field) {
            Some(offset) => LoadError::at_offset(&self.path, &self.text, offset, message),
            None => LoadError::new(&self.path, message),
        }
    }

    /// A rig or table reference of the plan, resolved against the plan's folder.
    pub fn resolve(&self, reference: &Path) -> PathBuf {
        if reference
            .to_str()
            .is_some_and(|s| s.starts_with("builtin:"))
        {
            return reference.to_path_buf();
        }
        crate::io::reference::resolve(&self.path, reference)
    }

    fn check(&self) -> Result<(), LoadError> {
        let f = &self.file;
        if f.version != PLAN_VERSION {
            return Err(self.field_error(
                "version",
                format!(
                    "plan version {} is not supported (this grimace reads {PLAN_VERSION})",
                    f.version
                ),
            ));
        }
        self.check_faces()?;
        if f.show.is_empty() {
            return Err(self.field_error("show", "`show` is empty: name at least one state"));
        }
        if f.outputs.is_empty() {
            return Err(self.field_error("outputs", "`outputs` is empty: name at least one format"));
        }
        for letter in &f.intensities {
            intensity_letter(letter)
                .ok_or_else(|| self.error_at("intensities", letter, bad_letter(letter)))?;
        }
        for (field, (w, h), max) in [
            ("size", f.size, MAX_IMAGE_SIDE),
            ("text_size", f.text_size, MAX_TEXT_SIDE),
        ] {
            if w == 0 || h == 0 || w > max || h > max {
                return Err(self.field_error(
                    field,
                    format!("`{field}` ({w}, {h}): each side must be 1 to {max}"),
                ));
            }
        }
        for view in &f.views {
            if !(view.yaw.is_finite() && view.pitch.is_finite()) {
                return Err(
                    self.field_error("views", "a view's yaw and pitch must be finite degrees")
                );
            }
        }
        for show in &f.show {
            self.check_show(show)?;
        }
        Ok(())
    }

    fn check_faces(&self) -> Result<(), LoadError> {
        if self.file.faces.is_empty() {
            return Err(self.field_error("faces", "`faces` is empty: name at least one rig"));
        }
        for (i, face) in self.file.faces.iter().enumerate() {
            let safe = !face.name.is_empty()
                && face.name.len() <= 64
                && face
                    .name
                    .chars()
                    .all(|c| c.is_ascii_alphanumeric() || c == '-' || c == '_');
            if !safe {
                return Err(self.error_at(
                    "faces",
                    &face.name,
                    format!(
                        "face name `{}`: use 1 to 64 letters, digits, `-` and `_` (it names a folder)",
                        face.name
                    ),
                ));
            }
            if self.file.faces[..i]
                .iter()
                .any(|f| f.name.eq_ignore_ascii_case(&face.name))
            {
                return Err(self.error_at(
                    "faces",
                    &face.name,
                    format!("face name `{}` is given twice", face.name),
                ));
            }
        }
        Ok(())
    }

    fn check_show(&self, show: &Show) -> Result<(), LoadError> {
        match show {
            Show::Aus(keys) | Show::Pairs(keys) | Show::Triples(keys) => {
                for key in keys {
                    self.au_key("show", key)?;
                }
            }
            Show::Combos(combos) => {
                for combo in combos {
                    self.combo(combo)?;
                }
            }
            Show::Random { .. } => self.check_random(&show.random().unwrap_or_default())?,
            Show::Neutral | Show::AllAus | Show::AllExpressions | Show::Expressions(_) => {}
        }
        Ok(())
    }

    fn check_random(&self, spec: &RandomSpec) -> Result<(), LoadError> {
        for key in &spec.aus {
            self.au_key("aus", key)?;
        }
        for c in spec.letters.chars() {
            if letter_factor(c).is_none() {
                return Err(self.error_at("letters", &spec.letters, bad_letter(&c.to_string())));
            }
        }
        let (lo, hi) = spec.terms;
        if spec.letters.is_empty() || lo == 0 || lo > hi || hi as usize > spec.aus.len() {
            return Err(self.field_error(
                "terms",
                format!(
                    "Random: terms ({lo}, {hi}) must run from 1 up to the number of AUs given ({}), with letters to draw from",
                    spec.aus.len()
                ),
            ));
        }
        Ok(())
    }

    /// Parses an AU key written in the plan, naming its place when it is not one.
    pub fn au_key(&self, field: &str, text: &str) -> Result<AuKey, LoadError> {
        text.parse::<AuKey>()
            .map_err(|e| self.error_at(field, text, e.to_string()))
    }

    /// Parses a FACS combination written in the plan, naming the place of a bad term.
    pub fn combo(&self, text: &str) -> Result<Combo, LoadError> {
        parse_combo(text).map_err(|e| {
            let field_at = ron_text::find_field(&self.text, 0, "show").unwrap_or(0);
            let message = format!("combination `{text}`: {}", e.message);
            match ron_text::find_string(&self.text, field_at, text) {
                // The string's opening quote, then the column within it.
                Some(at) => {
                    let inner: usize = text.chars().take(e.column - 1).map(char::len_utf8).sum();
                    LoadError::at_offset(&self.path, &self.text, at + 1 + inner, message)
                }
                None => LoadError::new(&self.path, message),
            }
        })
    }
}

/// The FACS intensity letter a plan's `intensities` entry names, upper case.
pub fn intensity_letter(text: &str) -> Option<char> {
    let mut chars = text.trim().chars();
    let c = chars.next()?;
    (chars.next().is_none() && letter_factor(c).is_some()).then(|| c.to_ascii_uppercase())
}

fn bad_letter(text: &str) -> String {
    format!("`{text}` is not a FACS intensity letter (A, B, C, D or E)")
}
