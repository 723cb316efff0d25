//! A plan expanded into items: one file each, with a stable ID, in a fixed order that
//! shards split.
//!
//! Order: faces as listed; for each face its states (the `show` entries in order, each
//! state once); for each state the outputs as listed; for a picture output every view, then
//! every style. An item's ID is the first 16 hex digits of the SHA-256 of its key text
//! ([`item_key`]): the face's name, the state's FACS code, the output, and for pictures the
//! view, style and size. The same plan gives the same IDs and files on every machine.

use std::collections::{BTreeMap, HashSet};

use sha2::{Digest, Sha256};

use super::plan::{intensity_letter, Output, Plan, RandomSpec, Show, StyleName, ViewSpec};
use crate::facs::combo::{Combo, Intensity, Term};
use crate::facs::{AuKey, AuTable};
use crate::io::error::LoadError;
use crate::model::{Activations, Rig};

/// One state of a face: what it shows and the activations that show it.
#[derive(Debug, Clone)]
pub struct State {
    /// The FACS code in canonical form (`1C+2C`; empty for the rest face).
    pub code: String,
    /// Each AU with its intensity factor (repeats added), in AU order.
    pub aus: Vec<(AuKey, f32)>,
    /// The muscle activations and jaw.
    pub act: Activations,
}

/// One file of the batch.
#[derive(Debug, Clone, PartialEq)]
pub struct Item {
    /// The item's stable ID (16 hex digits).
    pub id: String,
    /// Index into the faces.
    pub face: usize,
    /// Index into the face's states.
    pub state: usize,
    /// The state's place among every face's states (the unit shards split).
    pub group: usize,
    /// The file format.
    pub output: Output,
    /// The view (pictures only).
    pub view: Option<ViewSpec>,
    /// The style (pictures only).
    pub style: Option<StyleName>,
    /// Width and height: pixels, or columns and rows for text; none for meshes.
    pub size: Option<(u32, u32)>,
    /// The file, relative to the output folder: `FACE/ID[..2]/ID.EXT`.
    pub file: String,
}

/// How a picture is drawn: the view, the style and the size.
pub type Picture = (ViewSpec, StyleName, (u32, u32));

/// A face as the expansion needs it.
#[derive(Debug, Clone, Copy)]
pub struct FaceRef<'a> {
    /// The rig.
    pub rig: &'a Rig,
    /// Its AU table.
    pub table: &'a AuTable,
}

/// A plan's states and items.
#[derive(Debug, Clone)]
pub struct Expanded {
    /// The states of each face.
    pub states: Vec<Vec<State>>,
    /// Every item, in plan order.
    pub items: Vec<Item>,
}

/// Expands a plan on its faces (given in the plan's order), checking every AU, combination
/// and expression against the face's table.
pub fn expand(plan: &Plan, faces: &[FaceRef]) -> Result<Expanded, LoadError> {
    let mut states = Vec::with_capacity(faces.len());
    for (spec, face) in plan.file.faces.iter().zip(faces) {
        states.push(face_states(plan, &spec.name, *face)?);
    }
    let items = items(plan, &states)?;
    Ok(Expanded { states, items })
}

/// The text an item's ID is the hash of (documented in docs/batch.md).
pub fn item_key(face: &str, code: &str, output: Output, picture: Option<Picture>) -> String {
    let mut key = format!(
        "grimace-batch-item-v1\nface={face}\nstate={code}\noutput={}\n",
        output.ext()
    );
    if let Some((view, style, (w, h))) = picture {
        key.push_str(&format!(
            "yaw={}\npitch={}\nstyle={}\nsize={w}x{h}\n",
            view.yaw,
            view.pitch,
            style.style().name()
        ));
    }
    key
}

/// The lower-case hex SHA-256 of some bytes.
pub fn sha256_hex(bytes: &[u8]) -> String {
    let digest = Sha256::digest(bytes);
    let mut out = String::with_capacity(64);
    for b in digest {
        out.push_str(&format!("{b:02x}"));
    }
    out
}

fn items(plan: &Plan, states: &[Vec<State>]) -> Result<Vec<Item>, LoadError> {
    let f = &plan.file;
    let views = if f.views.is_empty() {
        vec![ViewSpec {
            yaw: 0.0,
            pitch: 0.0,
        }]
    } else {
        f.views.clone()
    };
    let styles = if f.styles.is_empty() {
        vec![StyleName::Shaded]
    } else {
        f.styles.clone()
    };
    let mut items = Vec::new();
    let mut ids = HashSet::new();
    let mut group = 0;
    for (face, (spec, face_states)) in f.faces.iter().zip(states).enumerate() {
        for (state, st) in face_states.iter().enumerate() {
            group += 1;
            for &output in &f.outputs {
                let pictures: Vec<Option<Picture>> = if output.is_picture() {
                    let size = if output == Output::Txt {
                        f.text_size
                    } else {
                        f.size
                    };
                    views
                        .iter()
                        .flat_map(|&v| styles.iter().map(move |&s| Some((v, s, size))))
                        .collect()
                } else {
                    vec![None]
                };
                for picture in pictures {
                    let id = sha256_hex(item_key(&spec.name, &st.code, output, picture).as_bytes())
                        [..16]
                        .to_string();
                    if !ids.insert(id.clone()) {
                        return Err(LoadError::new(
                            &plan.path,
                            format!(
                                "face `{}`, state `{}`: the same {} is planned twice (a view, style or output listed twice?)",
                                spec.name,
                                st.code,
                                output.ext()
                            ),
                        ));
                    }
                    let file = format!("{}/{}/{id}.{}", spec.name, &id[..2], output.ext());
                    items.push(Item {
                        id,
                        face,
                        state,
                        group: group - 1,
                        output,
                        view: picture.map(|p| p.0),
                        style: picture.map(|p| p.1),
                        size: picture.map(|p| p.2),
                        file,
                    });
                }
            }
        }
    }
    Ok(items)
}

/// The states one face shows, each once, in the order the plan names them.
fn face_states(plan: &Plan, name: &str, face: FaceRef) -> Result<Vec<State>, LoadError> {
    let letters: Vec<Option<char>> = if plan.file.intensities.is_empty() {
        vec![None]
    } else {
        plan.file
            .intensities
            .iter()
            .map(|l| intensity_letter(l))
            .collect()
    };
    let mut combos: Vec<(Combo, &'static str)> = Vec::new();
    for show in &plan.file.show {
        match show {
            Show::Neutral => combos.push((Combo::default(), "show")),
            Show::AllAus => {
                let keys: Vec<AuKey> = face.table.aus.keys().copied().collect();
                lettered(&keys, 1, &letters, &mut combos);
            }
            Show::Aus(keys) | Show::Pairs(keys) | Show::Triples(keys) => {
                let size = match show {
                    Show::Pairs(_) => 2,
                    Show::Triples(_) => 3,
                    _ => 1,
                };
                let keys = plan_keys(plan, name, face, "show", keys)?;
                lettered(&keys, size, &letters, &mut combos);
            }
            Show::Combos(texts) => {
                for text in texts {
                    combos.push((plan.combo(text)?, "show"));
                }
            }
            Show::AllExpressions => {
                for name in face.table.expressions.keys() {
                    combos.push((expression(plan, face, name)?, "show"));
                }
            }
            Show::Expressions(names) => {
                for expr in names {
                    if !face.table.expressions.contains_key(expr) {
                        return Err(plan.error_at(
                            "show",
                            expr,
                            format!("face `{name}`: its table has no expression named `{expr}`"),
                        ));
                    }
                    combos.push((expression(plan, face, expr)?, "show"));
                }
            }
            Show::Random { .. } => {
                let spec = show.random().unwrap_or_default();
                let keys = plan_keys(plan, name, face, "aus", &spec.aus)?;
                for combo in
                    random_combos(&spec, &keys).map_err(|m| plan.field_error("count", m))?
                {
                    combos.push((combo, "aus"));
                }
            }
        }
    }
    states_of(plan, name, face, combos)
}

/// Each distinct combination once, in order, evaluated on the face; `field` names where a
/// combination came from for errors.
fn states_of(
    plan: &Plan,
    name: &str,
    face: FaceRef,
    combos: Vec<(Combo, &'static str)>,
) -> Result<Vec<State>, LoadError> {
    let mut seen = HashSet::new();
    let mut states = Vec::new();
    for (combo, field) in combos {
        let code = combo.to_string();
        if !seen.insert(code.clone()) {
            continue;
        }
        let act = face.table.evaluate(&combo, face.rig).map_err(|e| {
            let missing = face.table.missing(&combo);
            let literal = missing
                .first()
                .map(|k| k.to_string())
                .unwrap_or(code.clone());
            plan.error_at(
                field,
                &literal,
                format!("face `{name}`, state `{code}`: {e}"),
            )
        })?;
        states.push(State {
            aus: summed(&combo),
            code,
            act,
        });
    }
    Ok(states)
}

/// A named expression of the face's table, parsed.
fn expression(plan: &Plan, face: FaceRef, name: &str) -> Result<Combo, LoadError> {
    let text = &face.table.expressions[name];
    text.parse::<Combo>().map_err(|e| {
        plan.error_at(
            "show",
            name,
            format!("expression `{name}` (`{text}`) in the face's table: {e}"),
        )
    })
}

/// AU keys of the plan, each checked against the face's table.
fn plan_keys(
    plan: &Plan,
    name: &str,
    face: FaceRef,
    field: &str,
    texts: &[String],
) -> Result<Vec<AuKey>, LoadError> {
    let mut keys = Vec::with_capacity(texts.len());
    for text in texts {
        let key = plan.au_key(field, text)?;
        if !face.table.gives(key) {
            return Err(plan.error_at(
                field,
                text,
                format!("face `{name}`: AU {key} is not in its table (see `grimace list --table`)"),
            ));
        }
        keys.push(key);
    }
    Ok(keys)
}

/// Every `size`-subset of `keys` (in the order given), at each letter (`None`: as recorded).
fn lettered(
    keys: &[AuKey],
    size: usize,
    letters: &[Option<char>],
    out: &mut Vec<(Combo, &'static str)>,
) {
    for subset in subsets(keys.len(), size) {
        for &letter in letters {
            let terms = subset
                .iter()
                .map(|&i| Term {
                    key: keys[i],
                    intensity: letter.map_or(Intensity::Full, Intensity::Letter),
                })
                .collect();
            out.push((Combo { terms }, "show"));
        }
    }
}

/// The `size`-element subsets of `0..n` in lexicographic order.
fn subsets(n: usize, size: usize) -> Vec<Vec<usize>> {
    if size == 0 || size > n {
        return Vec::new();
    }
    let mut out = Vec::new();
    let mut pick: Vec<usize> = (0..size).collect();
    loop {
        out.push(pick.clone());
        let Some(i) = (0..size).rev().find(|&i| pick[i] < n - size + i) else {
            return out;
        };
        pick[i] += 1;
        for j in i + 1..size {
            pick[j] = pick[j - 1] + 1;
        }
    }
}

/// Each AU of a combination with its factor, repeats added, in AU order.
fn summed(combo: &Combo) -> Vec<(AuKey, f32)> {
    let mut sums: BTreeMap<AuKey, f32> = BTreeMap::new();
    for term in &combo.terms {
        *sums.entry(term.key).or_default() += term.intensity.factor();
    }
    sums.into_iter().collect()
}

/// SplitMix64: a small generator whose sequence is fixed by its definition (Steele, Lea &
/// Flood 2014), so a seed draws the same combinations on every machine and version.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A number below `n` (n > 0; the bias of the remainder is negligible for small n).
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }
}

/// `spec.count` distinct combinations: a size in `terms`, that many distinct AUs (written in
/// AU order), each at a random letter.
fn random_combos(spec: &RandomSpec, keys: &[AuKey]) -> Result<Vec<Combo>, String> {
    let letters: Vec<char> = spec
        .letters
        .chars()
        .map(|c| c.to_ascii_uppercase())
        .collect();
    let (lo, hi) = (spec.terms.0 as usize, spec.terms.1 as usize);
    let mut rng = SplitMix64(spec.seed);
    let mut seen = HashSet::new();
    let mut out = Vec::new();
    let mut tries = 0u64;
    while out.len() < spec.count as usize {
        tries += 1;
        if tries > 1000 + 100 * u64::from(spec.count) {
            return Err(format!(
                "Random: only {} distinct combinations could be drawn, {} asked for (give more AUs, letters or terms)",
                out.len(),
                spec.count
            ));
        }
        let size = lo + rng.below(hi - lo + 1);
        let mut pool: Vec<usize> = (0..keys.len()).collect();
        for i in 0..size {
            let j = i + rng.below(pool.len() - i);
            pool.swap(i, j);
        }
        let mut chosen: Vec<AuKey> = pool[..size].iter().map(|&i| keys[i]).collect();
        chosen.sort();
        let terms: Vec<Term> = chosen
            .into_iter()
            .map(|key| Term {
                key,
                intensity: Intensity::Letter(letters[rng.below(letters.len())]),
            })
            .collect();
        let combo = Combo { terms };
        if seen.insert(combo.to_string()) {
            out.push(combo);
        }
    }
    Ok(out)
}

/// A fixed, balanced share of the items: shard `index` of `count` takes the states whose
/// place in plan order is `index` modulo `count`, with all their files (every state has the
/// same number of files, so counts differ by at most one state's; the face is deformed once
/// for all of them).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// This shard, from 0.
    pub index: usize,
    /// How many shards.
    pub count: usize,
}

impl Shard {
    /// The whole plan.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Parses `K/N` (0 <= K < N).
    pub fn parse(text: &str) -> Result<Shard, String> {
        let bad = || format!("--shard {text}: expected K/N with 0 <= K < N, e.g. 0/4 (or `slurm`)");
        let (k, n) = text.split_once('/').ok_or_else(bad)?;
        let index: usize = k.trim().parse().map_err(|_| bad())?;
        let count: usize = n.trim().parse().map_err(|_| bad())?;
        if count == 0 || index >= count {
            return Err(format!(
                "--shard {text}: there is no shard {index} of {count} (shards run from 0 to N-1)"
            ));
        }
        Ok(Shard { index, count })
    }

    /// Whether the state at `group` (its place among all states) is this shard's.
    pub fn takes(&self, group: usize) -> bool {
        group % self.count == self.index
    }

    /// The file name of this shard's labels.
    pub fn labels_name(&self) -> String {
        format!("shard-{:05}-of-{:05}.csv", self.index, self.count)
    }
}

impl std::fmt::Display for Shard {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subsets_are_every_combination_once() {
        assert_eq!(subsets(4, 2).len(), 6);
        assert_eq!(subsets(5, 3).len(), 10);
        assert_eq!(subsets(3, 1), vec![vec![0], vec![1], vec![2]]);
        assert!(subsets(2, 3).is_empty());
    }

    #[test]
    fn splitmix_is_the_published_sequence() {
        // The reference implementation's first output for seed 1234567.
        let mut rng = SplitMix64(1234567);
        assert_eq!(rng.next(), 6457827717110365317);
    }

    #[test]
    fn shards_parse_and_split_evenly() {
        assert_eq!(Shard::parse("1/3"), Ok(Shard { index: 1, count: 3 }));
        assert!(Shard::parse("5/4").unwrap_err().contains("no shard 5 of 4"));
        assert!(Shard::parse("0/0").is_err());
        assert!(Shard::parse("x").is_err());
        let shards: Vec<usize> = (0..3)
            .map(|k| {
                (0..100)
                    .filter(|&i| Shard { index: k, count: 3 }.takes(i))
                    .count()
            })
            .collect();
        assert_eq!(shards, [34, 33, 33]);
    }

    #[test]
    fn item_ids_are_the_documented_hash() {
        let front = ViewSpec {
            yaw: 0.0,
            pitch: 0.0,
        };
        let key = item_key(
            "default",
            "",
            Output::Png,
            Some((front, StyleName::Shaded, (128, 128))),
        );
        assert_eq!(
            key,
            "grimace-batch-item-v1\nface=default\nstate=\noutput=png\nyaw=0\npitch=0\nstyle=shaded\nsize=128x128\n"
        );
        assert_eq!(&sha256_hex(key.as_bytes())[..16], "790eb6cfb811af09");
        let mesh = item_key("default", "1C+2C", Output::Obj, None);
        assert_eq!(
            mesh,
            "grimace-batch-item-v1\nface=default\nstate=1C+2C\noutput=obj\n"
        );
    }

    #[test]
    fn sha256_matches_the_standard_vector() {
        assert_eq!(
            sha256_hex(b"abc"),
            "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
        );
    }
}
