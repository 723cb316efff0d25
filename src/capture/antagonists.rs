//! Muscles that pull the landmarks against each other, found from the rig's landmark
//! Jacobian, not from their names: two muscles whose columns point against each other
//! (weighted cosine below `-`[`ANTAGONIST_COSINE`]) are an antagonist pair, and the pairs
//! joined through shared muscles make a group (on the default rig: each side's brow raisers
//! with its brow lowerers; each side's lid closer with its lid raiser).
//!
//! Within a group the landmarks cannot tell a muscle working less than in the neutral from
//! its antagonist working more, and the muscles' own readings trade one for the other: what
//! a group does is its net landmark motion, `sum_i J_i a_i` over its members.

use glam::DVec3;

use super::pose::landmark_weight;
use super::rig_model::LandmarkModel;
use super::solver::weighted_dot;

/// Two muscles whose landmark columns have a weighted cosine below minus this pull against
/// each other. 0.7: the pair's motions are mostly opposite (an angle over 135 degrees); the
/// zygomatic major against the angular depressor (-0.52) or the lip sphincter against the
/// smile's muscles (-0.4 to -0.6) move the corners along different lines and stay apart.
pub const ANTAGONIST_COSINE: f64 = 0.7;

/// A group of muscles joined by antagonist pairs.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    /// The muscles, by index, in the rig's order.
    pub members: Vec<usize>,
}

impl Group {
    /// The group's net landmark motion under the activations `a` (one per variable).
    pub fn net(&self, model: &LandmarkModel, a: &[f64]) -> Vec<DVec3> {
        let mut net = vec![DVec3::ZERO; model.rest().len()];
        for &i in &self.members {
            for (n, c) in net.iter_mut().zip(model.column(i)) {
                *n += *c * a[i];
            }
        }
        net
    }
}

/// The weights the landmark columns are compared with: the solve's ([`landmark_weight`]).
fn weights(model: &LandmarkModel) -> Vec<DVec3> {
    (0..model.rest().len()).map(landmark_weight).collect()
}

/// The rig's antagonist groups (two or more muscles each), from its landmark columns.
pub fn groups(model: &LandmarkModel) -> Vec<Group> {
    let w = weights(model);
    let m = model.muscle_count();
    let norms: Vec<f64> = (0..m)
        .map(|i| weighted_dot(&w, model.column(i), model.column(i)).sqrt())
        .collect();
    // Each muscle's group label; a pair joins its two labels.
    let mut label: Vec<usize> = (0..m).collect();
    for i in 0..m {
        for j in i + 1..m {
            if norms[i] <= 0.0 || norms[j] <= 0.0 {
                continue;
            }
            let cosine = weighted_dot(&w, model.column(i), model.column(j)) / (norms[i] * norms[j]);
            if cosine < -ANTAGONIST_COSINE {
                let (from, to) = (label[j], label[i]);
                label
                    .iter_mut()
                    .filter(|l| **l == from)
                    .for_each(|l| *l = to);
            }
        }
    }
    let mut out = Vec::new();
    for l in 0..m {
        let members: Vec<usize> = (0..m).filter(|&i| label[i] == l).collect();
        if members.len() > 1 {
            out.push(Group { members });
        }
    }
    out
}
