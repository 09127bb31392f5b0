//! Byte-level edits of the shipped scenes ([`mutations`]).

use crate::pools::pick;
use proptest::prelude::*;
use proptest::sample::Index;
use proptest::strategy::BoxedStrategy;

/// Byte-level mutations of the given scene texts: replaced, inserted,
/// deleted and duplicated bytes, TOML tokens and numbers inserted,
/// truncation; and, one in ten, any printable text.
pub fn mutations(scenes: Vec<String>) -> BoxedStrategy<String> {
    prop_oneof![9 => mutated(scenes), 1 => "\\PC{0,200}"].boxed()
}

pub(crate) fn mutated(scenes: Vec<String>) -> BoxedStrategy<String> {
    const INSERTS: [&str; 36] = [
        "0",
        "9",
        ".",
        "e",
        "-",
        "+",
        "_",
        "\"",
        "'",
        "[",
        "]",
        "{",
        "}",
        "=",
        ",",
        "\n",
        "\r\n",
        "#",
        "\\",
        "x",
        " ",
        "nan",
        "inf",
        "-inf",
        "1e400",
        "9223372036854775807",
        "18446744073709551615",
        "[bar]\n",
        "[beam]\n",
        "[output]\n",
        "\u{0}",
        "\u{feff}",
        "é",
        "\"\"\"",
        "1979-05-27T07:32:00Z",
        "[[bar]]\n",
    ];
    #[derive(Clone, Debug)]
    enum Op {
        Replace(Index, u8),
        Insert(Index, &'static str),
        Delete(Index, usize),
        Duplicate(Index, usize, Index),
        Truncate(Index),
    }
    let op = prop_oneof![
        4 => (any::<Index>(), any::<u8>()).prop_map(|(i, b)| Op::Replace(i, b)),
        6 => (any::<Index>(), pick(&INSERTS)).prop_map(|(i, s)| Op::Insert(i, s)),
        3 => (any::<Index>(), 1usize..16).prop_map(|(i, n)| Op::Delete(i, n)),
        2 => (any::<Index>(), 1usize..40, any::<Index>()).prop_map(|(i, n, j)| Op::Duplicate(i, n, j)),
        1 => any::<Index>().prop_map(Op::Truncate),
    ];
    (proptest::sample::select(scenes), prop::collection::vec(op, 1..6))
        .prop_map(|(text, ops)| {
            let mut b = text.into_bytes();
            for op in ops {
                let n = b.len();
                match op {
                    Op::Replace(i, c) if n > 0 => b[i.index(n)] = c,
                    Op::Insert(i, s) => {
                        let at = i.index(n + 1);
                        b.splice(at..at, s.bytes());
                    }
                    Op::Delete(i, k) if n > 0 => {
                        let at = i.index(n);
                        b.drain(at..(at + k).min(n));
                    }
                    Op::Duplicate(i, k, j) if n > 0 => {
                        let at = i.index(n);
                        let piece: Vec<u8> = b[at..(at + k).min(n)].to_vec();
                        let to = j.index(n + 1);
                        b.splice(to..to, piece);
                    }
                    Op::Truncate(i) => b.truncate(i.index(n + 1)),
                    _ => {}
                }
            }
            String::from_utf8_lossy(&b).into_owned()
        })
        .boxed()
}
