//! Which face of a recording is followed.
//!
//! OpenFace's `FaceLandmarkVidMulti` tracks every face in the picture and writes one row per
//! face and frame, told apart by `face_id`; `FeatureExtraction` writes one face, `face_id` 0.
//! Read as one sequence, two people's rows would alternate: `capture` would take one face's
//! landmarks as the other's motion and `play` would flicker between them. So one face is
//! followed: the one asked for (`--face ID`), else the face of the first tracked row, and the
//! rows of every other face are skipped, counted, and named at the end with the option that
//! follows them instead. A recording without a `face_id` column is one face.

use std::collections::BTreeMap;

/// The largest `face_id` accepted (OpenFace numbers its trackers from 0; a few dozen at most).
pub const MAX_FACE_ID: u32 = 1_000_000;

/// The face followed in a recording, and the rows of the others skipped so far.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Faces {
    /// The face asked for, if any.
    wanted: Option<u32>,
    /// The face followed once a tracked row has named it (or the one asked for).
    followed: Option<u32>,
    /// Rows skipped per other face.
    others: BTreeMap<u32, usize>,
    /// Whether the first row of another face has been told ([`Faces::take_notice`]).
    told: bool,
}

impl Faces {
    /// Follows face `wanted`, or (`None`) the face of the first tracked row.
    pub fn new(wanted: Option<u32>) -> Faces {
        Faces {
            wanted,
            followed: wanted,
            ..Faces::default()
        }
    }

    /// Whether a row of face `id` (`None`: the recording has no `face_id`) belongs to the
    /// followed face; `tracked` rows decide the face when none was asked for. Rows of other
    /// faces are counted.
    pub fn admits(&mut self, id: Option<u32>, tracked: bool) -> bool {
        let Some(id) = id else {
            return true;
        };
        let followed = match self.followed {
            Some(f) => f,
            // An untracked row before any face was seen counts as untracked, not as a face.
            None if !tracked => return true,
            None => *self.followed.insert(id),
        };
        if id == followed {
            return true;
        }
        *self.others.entry(id).or_default() += 1;
        false
    }

    /// The face followed, once known.
    pub fn followed(&self) -> Option<u32> {
        self.followed
    }

    /// Rows of other faces skipped so far.
    pub fn skipped(&self) -> usize {
        self.others.values().sum()
    }

    /// Once, when the first row of another face has been skipped: what is happening and how to
    /// follow that face instead.
    pub fn take_notice(&mut self) -> Option<String> {
        if self.told || self.others.is_empty() {
            return None;
        }
        self.told = true;
        let (other, _) = self.others.iter().next()?;
        Some(format!(
            "the recording holds more than one face (face_id {other} beside {}): following face {} and skipping the others' rows; --face {other} follows that one",
            self.followed.unwrap_or(0),
            self.followed.unwrap_or(0),
        ))
    }

    /// One line for the end of a run when rows of other faces were skipped:
    /// `followed face 0; skipped 380 rows of face 1 (--face ID follows another)`.
    pub fn summary(&self) -> Option<String> {
        if self.others.is_empty() {
            return None;
        }
        let skipped: Vec<String> = self
            .others
            .iter()
            .map(|(id, rows)| {
                let noun = if *rows == 1 { "row" } else { "rows" };
                format!("{rows} {noun} of face {id}")
            })
            .collect();
        Some(format!(
            "followed face {}; skipped {} (--face ID follows another)",
            self.followed.unwrap_or(0),
            skipped.join(", ")
        ))
    }

    /// The other faces met, in order of their ids: for an error when the face asked for is
    /// absent.
    pub fn others(&self) -> Vec<u32> {
        self.others.keys().copied().collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_first_tracked_face_is_followed_and_the_others_counted() {
        let mut faces = Faces::new(None);
        // An untracked row of face 1 before any tracked row does not choose the face.
        assert!(faces.admits(Some(1), false));
        assert!(faces.admits(Some(0), true));
        assert!(!faces.admits(Some(1), true));
        assert!(!faces.admits(Some(1), false));
        assert!(!faces.admits(Some(2), true));
        assert!(faces.admits(Some(0), false));
        assert_eq!(faces.followed(), Some(0));
        assert_eq!(faces.skipped(), 3);
        let notice = faces.take_notice().unwrap();
        assert!(notice.contains("following face 0"), "{notice}");
        assert!(notice.contains("--face 1"), "{notice}");
        assert_eq!(faces.take_notice(), None);
        assert_eq!(
            faces.summary().unwrap(),
            "followed face 0; skipped 2 rows of face 1, 1 row of face 2 (--face ID follows another)"
        );
    }

    #[test]
    fn the_face_asked_for_is_followed_and_one_face_says_nothing() {
        let mut faces = Faces::new(Some(1));
        assert!(!faces.admits(Some(0), true));
        assert!(faces.admits(Some(1), true));
        assert_eq!(faces.followed(), Some(1));
        assert_eq!(faces.others(), vec![0]);

        let mut one = Faces::new(None);
        for _ in 0..3 {
            assert!(one.admits(Some(0), true));
            assert!(one.admits(None, true));
        }
        assert_eq!(one.summary(), None);
        assert_eq!(one.take_notice(), None);
    }
}
