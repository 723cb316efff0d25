//! A big rig's per-vertex weights read without RON's general parser.
//!
//! A rig fitted to a big head is megabytes of `(vertex, weight)` pairs in its masks and jaw,
//! and RON's parser reads them at a few megabytes a second: most of the editor's wait for
//! its first screen. [`lift`] finds each `weights: [ ... ]` list written the plain way
//! grimace writes it (pairs of an integer and a number, commas, whitespace), reads it here
//! and leaves in its place a one-pair marker `(INDEX, NaN)` padded with the list's own
//! newlines and spaces, so the rest of the file keeps its lines and columns for RON's
//! error messages. [`Lifted::restore`] puts the lists back where their markers were read.
//! A list written another way (comments, other spellings) is left for RON, and when the
//! markers do not come back one for one (a marker spelled inside a string, a user's own
//! `(0, NaN)`), the caller parses the original text instead: the result is always what RON
//! alone reads from the file.

/// Lists shorter than this (in bytes of text) are left for RON.
const MIN_LIST: usize = 256;

/// A rig's text with its big weight lists lifted out.
#[derive(Debug)]
pub(super) struct Lifted {
    /// The text with a marker in place of each lifted list.
    pub text: String,
    lists: Vec<Option<Vec<(u32, f32)>>>,
}

/// Lifts the big weight lists out of `text`; `None` when there is none.
pub(super) fn lift(text: &str) -> Option<Lifted> {
    let mut out = String::new();
    let mut lists = Vec::new();
    let mut copied = 0;
    let mut from = 0;
    while let Some(found) = text[from..].find("weights:") {
        let start = from + found + "weights:".len();
        from = start;
        let Some(open) = text[start..]
            .find(|c: char| !c.is_whitespace())
            .map(|i| start + i)
            .filter(|&i| text.as_bytes()[i] == b'[')
        else {
            continue;
        };
        let Some((pairs, close)) = read_pairs(text, open + 1) else {
            continue;
        };
        let body = &text[open + 1..close];
        let marker = format!("({}, NaN)", lists.len());
        if body.len() < MIN_LIST {
            continue;
        }
        // the list's newlines kept, the rest blanked (later lines and columns stay), the
        // marker written over the first stretch of blanks long enough
        let mut blank: Vec<u8> = body
            .bytes()
            .map(|b| if b == b'\n' { b'\n' } else { b' ' })
            .collect();
        let Some(at) = blank
            .windows(marker.len())
            .position(|w| w.iter().all(|&b| b == b' '))
        else {
            continue;
        };
        blank[at..at + marker.len()].copy_from_slice(marker.as_bytes());
        out.push_str(&text[copied..open + 1]);
        out.push_str(std::str::from_utf8(&blank).expect("ASCII"));
        copied = close;
        from = close;
        lists.push(Some(pairs));
    }
    if lists.is_empty() {
        return None;
    }
    out.push_str(&text[copied..]);
    Some(Lifted { text: out, lists })
}

/// Reads `(u32, f32)` pairs from `at` up to the closing `]`: the pairs and the bracket's
/// position, or `None` for anything but plain pairs.
fn read_pairs(text: &str, mut at: usize) -> Option<(Vec<(u32, f32)>, usize)> {
    let bytes = text.as_bytes();
    let skip = |at: &mut usize| {
        while bytes.get(*at).is_some_and(|b| b.is_ascii_whitespace()) {
            *at += 1;
        }
    };
    let token = |at: &mut usize, ok: fn(u8) -> bool| {
        let start = *at;
        while bytes.get(*at).is_some_and(|&b| ok(b)) {
            *at += 1;
        }
        &text[start..*at]
    };
    let expect = |at: &mut usize, b: u8| {
        skip(at);
        let found = bytes.get(*at) == Some(&b);
        *at += usize::from(found);
        found
    };
    let mut pairs = Vec::new();
    loop {
        skip(&mut at);
        match bytes.get(at)? {
            b']' => return Some((pairs, at)),
            b'(' => at += 1,
            _ => return None,
        }
        skip(&mut at);
        let vertex: u32 = token(&mut at, |b| b.is_ascii_digit()).parse().ok()?;
        if !expect(&mut at, b',') {
            return None;
        }
        skip(&mut at);
        let number = token(&mut at, |b| b.is_ascii_digit() || b"+-.eE".contains(&b));
        if !plain_number(number) {
            return None;
        }
        let weight: f32 = number.parse().ok()?;
        if !expect(&mut at, b')') {
            return None;
        }
        pairs.push((vertex, weight));
        // a comma between pairs, optional after the last one (as RON has it)
        if !expect(&mut at, b',') && !expect(&mut at, b']') {
            return None;
        }
        if bytes[at - 1] == b']' {
            return Some((pairs, at - 1));
        }
    }
}

/// True for `-?D+(.D+)?([eE][+-]?D+)?` (D a digit): the numbers grimace writes, which RON
/// and Rust's `f32` parse read alike; anything else is left for RON.
fn plain_number(text: &str) -> bool {
    let digits = |s: &str| s.len() - s.trim_start_matches(|c: char| c.is_ascii_digit()).len();
    let mut rest = text.strip_prefix('-').unwrap_or(text);
    let whole = digits(rest);
    rest = &rest[whole..];
    if whole == 0 {
        return false;
    }
    if let Some(after) = rest.strip_prefix('.') {
        let n = digits(after);
        if n == 0 {
            return false;
        }
        rest = &after[n..];
    }
    if let Some(after) = rest.strip_prefix(['e', 'E']) {
        let after = after.strip_prefix(['+', '-']).unwrap_or(after);
        let n = digits(after);
        if n == 0 {
            return false;
        }
        rest = &after[n..];
    }
    rest.is_empty()
}

impl Lifted {
    /// Puts the lifted lists back in place of their markers among `found` (every weight
    /// list RON read from the lifted text); false, with the lists left as they are, when
    /// the markers do not come back exactly once each.
    pub(super) fn restore<'a>(
        mut self,
        found: impl IntoIterator<Item = &'a mut Vec<(u32, f32)>>,
    ) -> bool {
        let mut places = Vec::new();
        for list in found {
            if let [(index, w)] = list[..] {
                if w.is_nan() {
                    places.push((index as usize, list));
                }
            }
        }
        if places.len() != self.lists.len() {
            return false;
        }
        let mut order: Vec<usize> = places.iter().map(|(i, _)| *i).collect();
        order.sort_unstable();
        if order.iter().enumerate().any(|(k, &i)| k != i) {
            return false;
        }
        for (index, list) in places {
            *list = self.lists[index].take().unwrap_or_default();
        }
        true
    }
}

#[cfg(test)]
mod tests {
    use super::super::{parse_file, ron_text, RigFile};
    use super::*;
    use crate::io::{builtin, rig_to_ron};
    use crate::model::{Mask, Rig};
    use std::path::Path;

    /// The built-in rig with two masks of awkward weights, as grimace writes it.
    fn rig_text() -> (Rig, String) {
        let mut rig = builtin::default_rig();
        let weights = |k: u32| -> Vec<(u32, f32)> {
            (0..400u32)
                .map(|v| (v * k, ((v * 7919 % 1000) as f32 / 999.0).powf(1.7)))
                .collect()
        };
        let names = vec![rig.muscles[0].name.clone()];
        rig.masks = vec![
            Mask {
                muscles: names.clone(),
                gain: 1.0,
                weights: weights(3),
            },
            Mask {
                muscles: names,
                gain: 0.5,
                weights: vec![(1, 1e-7), (2, 0.0), (5, 1.0)],
            },
        ];
        let text = rig_to_ron(&rig);
        (rig, text)
    }

    fn by_ron(text: &str) -> Rig {
        let file: RigFile = ron_text::parse(Path::new("t.rig.ron"), text, "a rig").unwrap();
        file.into_rig()
    }

    #[test]
    fn lifted_lists_read_as_ron_reads_them_with_lines_kept() {
        let (rig, text) = rig_text();
        let lifted = lift(&text).expect("lists to lift");
        assert!(lifted.lists.len() >= 2, "the jaw's and the big mask's");
        assert_eq!(lifted.text.lines().count(), text.lines().count());
        let fast = parse_file(Path::new("t.rig.ron"), &text)
            .unwrap()
            .into_rig();
        assert_eq!(fast, by_ron(&text));
        assert_eq!(fast.masks, rig.masks);
        // every bit of every weight, not only equal values
        let bits = |r: &Rig| -> Vec<u32> {
            let m = r.masks.iter().flat_map(|m| m.weights.iter());
            let j = r.jaw.iter().flat_map(|j| j.weights.iter());
            m.chain(j).map(|&(v, w)| v ^ w.to_bits()).collect()
        };
        assert_eq!(bits(&fast), bits(&by_ron(&text)));
    }

    #[test]
    fn anything_but_plain_pairs_is_left_to_ron() {
        let (_, text) = rig_text();
        // a user's own marker-like pair: the markers no longer come back one for one
        let odd = text.replacen("(3, ", "(0, NaN), (3, ", 1);
        let fast = parse_file(Path::new("t.rig.ron"), &odd).map(|f| f.into_rig());
        // NaN is not equal to itself: compared by their text
        assert_eq!(
            format!("{:?}", fast.ok()),
            format!("{:?}", Some(by_ron(&odd)))
        );
        for bad in [
            "(3, .5)",
            "(3, 1.)",
            "(3, +1)",
            "(3 0.5)",
            "(3, 0.5) (4, 0.5)",
        ] {
            assert!(read_pairs(&format!("{bad}]"), 0).is_none(), "{bad}");
        }
        assert_eq!(read_pairs("(3, 0.5), (4, 1e-7),\n]", 0).unwrap().0.len(), 2);
        // a damaged list reports RON's own error, at its place in the original text
        let broken = text.replacen("(3, ", "(3,, ", 1);
        let fast = parse_file(Path::new("t.rig.ron"), &broken).err().unwrap();
        let slow = ron_text::parse::<RigFile>(Path::new("t.rig.ron"), &broken, "a rig");
        assert_eq!(fast.to_string(), slow.err().unwrap().to_string());
    }
}
