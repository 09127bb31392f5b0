//! The mass treatments at several contact nodes
//! (`Bar::mass_with_contacts`, `Bar::mass_all_nodes_with_contacts`,
//! docs/theory.md §2.1.2 and its several-contacts paragraph):
//!
//! * one contact node 0 is the single-contact matrix, bit for bit;
//! * contacts at both ends of a `2m`-element bar on `[0, 2]` (the mirrored
//!   benchmark) give, on nodes `0..=m`, the `m`-element single-contact
//!   matrix on `[0, 1]` with the middle node's diagonal doubled, bit for
//!   bit, and a matrix symmetric under `i ↦ 2m − i`;
//! * interior contact nodes against a dense matrix assembled here from the
//!   rules of the doc comment (element weights, then node-level moves);
//! * the total mass `1ᵀM1` against closed forms;
//! * every refusal, with the node it names.
//!
//! Entries are sums of at most four terms, so the dense comparison is to
//! 1e-15 relative (measured: exact or one ulp) and totals to 1e-14.

use crate::common;

use common::assert_matrix_eq;
use faer::Mat;
use signorini_fem::{Bar, BarMass, FemError, RightEnd, SymBand};

const ALL: [BarMass; 8] = BarMass::ALL;
const MASSLESS: [BarMass; 6] = [BarMass::Mod, BarMass::Mod1, BarMass::Mod2, BarMass::Mod3, BarMass::Transfer, BarMass::Singular];

fn bits(a: &SymBand) -> Vec<u64> {
    (0..a.n()).flat_map(|i| (i.saturating_sub(1)..=i).map(move |j| a.get(i, j).to_bits())).collect()
}

#[test]
fn one_contact_at_node_0_is_the_single_contact_matrix_bit_for_bit() {
    for mass in ALL {
        for m in [2, 3, 7, 40] {
            for end in [RightEnd::Clamped, RightEnd::Free] {
                let b = Bar::new(1.3, m, 0.7, end).unwrap();
                assert_eq!(bits(&b.mass_all_nodes_with_contacts(mass, &[0]).unwrap()), bits(&b.mass_all_nodes(mass)), "{mass} m = {m} all nodes");
                assert_eq!(bits(&b.mass_with_contacts(mass, &[0]).unwrap()), bits(&b.mass(mass)), "{mass} m = {m} {end:?}");
            }
        }
    }
}

#[test]
fn both_ends_of_the_mirrored_bar_repeat_the_single_contact_matrix() {
    for mass in ALL {
        for m in [2, 3, 5, 20] {
            let single = Bar::new(1.0, m, 1.0, RightEnd::Clamped).unwrap().mass_all_nodes(mass);
            let two = Bar::new(2.0, 2 * m, 1.0, RightEnd::Free).unwrap();
            let mm = two.mass_with_contacts(mass, &[0, 2 * m]).unwrap_or_else(|e| panic!("{mass} m = {m}: {e}"));
            assert_eq!(mm.n(), 2 * m + 1);
            for i in 0..=m {
                for j in i.saturating_sub(1)..=i {
                    let want = if i == m && j == m { 2.0 * single.get(m, m) } else { single.get(i, j) };
                    assert_eq!(mm.get(i, j).to_bits(), want.to_bits(), "{mass} m = {m}: entry ({i},{j}) = {} vs {want}", mm.get(i, j));
                }
            }
            for i in 0..=2 * m {
                for j in i.saturating_sub(1)..=i {
                    assert_eq!(mm.get(i, j).to_bits(), mm.get(2 * m - j, 2 * m - i).to_bits(), "{mass} m = {m}: mirror of ({i},{j})");
                }
            }
        }
    }
}

/// The doc comment's rules, written here on a dense matrix of all nodes.
fn hand_built(mass: BarMass, m: usize, length: f64, nodes: &[usize]) -> Mat<f64> {
    let h = length / m as f64;
    let mut w = vec![1.0; m];
    let emptied: Vec<(usize, usize)> = nodes.iter().flat_map(|&i| [(i as i64 - 1, i), (i as i64, i)]).filter(|&(j, _)| j >= 0 && (j as usize) < m).map(|(j, i)| (j as usize, i)).collect();
    if matches!(mass, BarMass::Mod | BarMass::Mod1 | BarMass::Mod2 | BarMass::Mod3) {
        for &(j, _) in &emptied {
            w[j] = 0.0;
        }
        let z = w.iter().filter(|x| **x == 0.0).count() as f64;
        if mass == BarMass::Mod2 {
            for x in w.iter_mut().filter(|x| **x != 0.0) {
                *x = m as f64 / (m as f64 - z);
            }
        }
        if mass == BarMass::Mod3 {
            for &(j, i) in &emptied {
                // The next element away from node i.
                let next = if j == i { j + 1 } else { j - 1 };
                w[next] += 1.0;
            }
        }
    }
    let mut a = Mat::<f64>::zeros(m + 1, m + 1);
    for (j, wj) in w.iter().enumerate() {
        let (d, o) = if mass == BarMass::Lumped { (wj * h / 2.0, 0.0) } else { (wj * h / 3.0, wj * h / 6.0) };
        a[(j, j)] += d;
        a[(j + 1, j + 1)] += d;
        a[(j, j + 1)] += o;
        a[(j + 1, j)] += o;
    }
    match mass {
        BarMass::Transfer => {
            let mut moves = Vec::new();
            for &i in nodes {
                let row: f64 = (0..=m).map(|j| a[(i, j)]).sum();
                let sides: Vec<usize> = [i as i64 - 1, i as i64 + 1].into_iter().filter(|&j| j >= 0 && j as usize <= m).map(|j| j as usize).collect();
                for &j in &sides {
                    moves.push((j, row / sides.len() as f64));
                }
            }
            for (j, v) in moves {
                a[(j, j)] += v;
            }
            for &i in nodes {
                for k in 0..=m {
                    a[(i, k)] = 0.0;
                    a[(k, i)] = 0.0;
                }
            }
        }
        BarMass::Singular => {
            for &i in nodes {
                for k in 0..=m {
                    a[(i, k)] = 0.0;
                    a[(k, i)] = 0.0;
                }
                let nb = if i == 0 { 1 } else { m - 1 };
                a[(nb, nb)] = 7.0 * h / 12.0;
            }
        }
        _ => {}
    }
    a
}

fn total(a: &SymBand) -> f64 {
    a.quad_form(&vec![1.0; a.n()])
}

#[test]
fn interior_and_end_contact_nodes_follow_the_documented_rules() {
    let cases: [(usize, &[usize]); 6] = [(10, &[0, 5, 10]), (10, &[3, 7]), (12, &[0, 4, 8, 12]), (9, &[2, 6]), (20, &[0, 10, 20]), (7, &[0, 7])];
    for mass in ALL {
        for (m, nodes) in cases {
            let b = Bar::new(2.5, m, 1.0, RightEnd::Free).unwrap();
            let got = match b.mass_all_nodes_with_contacts(mass, nodes) {
                Ok(g) => g,
                Err(e) => {
                    // singular: end nodes only (checked in the refusals test).
                    assert!(mass == BarMass::Singular && nodes.iter().any(|&i| i != 0 && i != m), "{mass} {nodes:?}: {e}");
                    continue;
                }
            };
            let want = hand_built(mass, m, 2.5, nodes);
            assert_matrix_eq(&got, &want, 1e-15, &format!("{mass} m = {m} contacts {nodes:?}"));
            let h = 2.5 / m as f64;
            if mass.massless_contact_node() {
                for &i in nodes {
                    assert!((0..=m).all(|j| got.get(i, j) == 0.0), "{mass}: contact node {i} keeps mass");
                }
                for i in (0..=m).filter(|i| !nodes.contains(i)) {
                    assert!(got.get(i, i) > 0.0, "{mass}: node {i} left without mass");
                }
            }
            // Total mass 1ᵀM1 in closed form: z emptied elements (mod),
            // h/6 per end contact node and h/3 per interior one (transfer),
            // 3h/4 per end node (singular), L otherwise.
            let z = (0..m).filter(|&j| nodes.contains(&j) || nodes.contains(&(j + 1))).count() as f64;
            let ends = nodes.iter().filter(|&&i| i == 0 || i == m).count() as f64;
            let inner = nodes.len() as f64 - ends;
            let want_total = match mass {
                BarMass::Mod | BarMass::Mod1 => 2.5 - z * h,
                BarMass::Transfer => 2.5 - ends * h / 6.0 - inner * h / 3.0,
                BarMass::Singular => 2.5 - ends * 3.0 * h / 4.0,
                _ => 2.5,
            };
            assert!((total(&got) - want_total).abs() <= 1e-14, "{mass} {nodes:?}: total {} vs {want_total}", total(&got));
        }
    }
}

#[test]
fn refusals_name_the_node() {
    let bar = |m: usize| Bar::new(1.0, m, 1.0, RightEnd::Free).unwrap();
    let refused = |mass: BarMass, m: usize, nodes: &[usize], node: usize, why: &str| match bar(m).mass_all_nodes_with_contacts(mass, nodes) {
        Err(FemError::MassAtContacts { mass: name, node: n, why: w }) => {
            assert_eq!((name, n), (mass.name(), node), "{mass} {nodes:?}: {w}");
            assert!(w.contains(why), "{mass} {nodes:?}: {w:?} does not say {why:?}");
        }
        other => panic!("{mass} {nodes:?}: expected a refusal at node {node}, got {other:?}"),
    };
    // Adjacent contact nodes: transfer would move mass onto a contact node.
    refused(BarMass::Transfer, 10, &[3, 4], 3, "must not be contact nodes");
    refused(BarMass::Transfer, 10, &[0, 1], 0, "must not be contact nodes");
    // mod3: the next element away is emptied by another contact, or missing.
    refused(BarMass::Mod3, 10, &[0, 2], 0, "mod3");
    refused(BarMass::Mod3, 10, &[3, 5], 3, "mod3");
    refused(BarMass::Mod3, 10, &[1], 1, "mod3");
    refused(BarMass::Mod3, 10, &[9], 9, "mod3");
    // singular: end nodes only.
    refused(BarMass::Singular, 10, &[0, 5], 5, "end node only");
    // A node that is not a contact node left without mass.
    refused(BarMass::Mod, 10, &[0, 2], 1, "without mass");
    refused(BarMass::Mod2, 10, &[4, 6], 5, "without mass");
    // Every element emptied, and a node beyond m.
    refused(BarMass::Mod2, 2, &[0, 2], 0, "every element");
    refused(BarMass::Std, 10, &[11], 11, "beyond");
    // The clamped end's node is not an unknown.
    match Bar::new(1.0, 10, 1.0, RightEnd::Clamped).unwrap().mass_with_contacts(BarMass::Mod, &[0, 10]) {
        Err(FemError::MassAtContacts { node: 10, .. }) => {}
        other => panic!("clamped node m accepted: {other:?}"),
    }
    // Accepted at the limit of each rule: mod3 three elements apart and two
    // from an end, transfer two apart, singular at both ends.
    for (mass, m, nodes) in [
        (BarMass::Mod3, 10, vec![2, 5, 8]),
        (BarMass::Mod3, 10, vec![0, 3]),
        (BarMass::Mod3, 4, vec![0, 4]),
        (BarMass::Transfer, 10, vec![0, 2, 4]),
        (BarMass::Singular, 10, vec![0, 10]),
        (BarMass::Mod, 10, vec![0, 3]),
    ] {
        assert!(bar(m).mass_all_nodes_with_contacts(mass, &nodes).is_ok(), "{mass} {nodes:?}");
    }
    // The massive treatments accept anything in range.
    for mass in [BarMass::Std, BarMass::Lumped] {
        assert_eq!(bits(&bar(6).mass_all_nodes_with_contacts(mass, &[0, 1, 2, 6]).unwrap()), bits(&bar(6).mass_all_nodes(mass)));
    }
    let _ = MASSLESS;
}

/// `transfer` at an interior contact node next to the far end, by hand:
/// m = 4 on `[0, 1]` (h = 1/4), contacts at nodes 0 and 3. The consistent
/// mass on all nodes has diagonal `h/3, 2h/3, 2h/3, 2h/3, h/3` and
/// off-diagonal `h/6`. Row sums: node 0 (end) `h/3 + h/6 = h/2`, all of it
/// to node 1; node 3 (interior) `h/6 + 2h/3 + h/6 = h`, half to node 2 and
/// half to node 4 — the far end node is a neighbour like any other. Rows
/// and columns 0 and 3 are then zeroed:
///
/// ```text
/// M11 = 2h/3 + h/2 = 7h/6 = 7/24    M12 = h/6 = 1/24
/// M22 = 2h/3 + h/2 = 7h/6 = 7/24    M23 = M34 = M01 = 0
/// M44 = h/3 + h/2 = 5h/6 = 5/24     M00 = M33 = 0
/// ```
///
/// Clamped, node 4 is dropped (its share of node 3's row goes with it):
/// the unknowns 0..=3 keep the same entries. Each entry is at most three
/// rounded terms: 2 ulp.
#[test]
fn transfer_next_to_the_far_end_by_hand() {
    #[rustfmt::skip]
    let want_all: [[f64; 5]; 5] = [
        [0.0, 0.0,         0.0,        0.0, 0.0],
        [0.0, 7.0 / 24.0,  1.0 / 24.0, 0.0, 0.0],
        [0.0, 1.0 / 24.0,  7.0 / 24.0, 0.0, 0.0],
        [0.0, 0.0,         0.0,        0.0, 0.0],
        [0.0, 0.0,         0.0,        0.0, 5.0 / 24.0],
    ];
    let check = |got: &SymBand, n: usize, what: &str| {
        assert_eq!(got.n(), n, "{what}");
        for i in 0..n {
            for j in i.saturating_sub(1)..=i {
                let w = want_all[i][j];
                assert!((got.get(i, j) - w).abs() <= 2.0 * f64::EPSILON * w.abs(), "{what}: M{i}{j} = {} by hand {w}", got.get(i, j));
            }
        }
    };
    let free = Bar::new(1.0, 4, 1.0, RightEnd::Free).unwrap();
    check(&free.mass_all_nodes_with_contacts(BarMass::Transfer, &[0, 3]).unwrap(), 5, "all nodes");
    check(&free.mass_with_contacts(BarMass::Transfer, &[0, 3]).unwrap(), 5, "free");
    check(&free.mass_with_contacts(BarMass::Transfer, &[3, 0]).unwrap(), 5, "free, contacts unsorted");
    let clamped = Bar::new(1.0, 4, 1.0, RightEnd::Clamped).unwrap();
    check(&clamped.mass_with_contacts(BarMass::Transfer, &[0, 3]).unwrap(), 4, "clamped");
}
