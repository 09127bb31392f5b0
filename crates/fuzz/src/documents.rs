//! Documents from the scene grammar ([`documents`]).

use crate::bar::{assemble_bar, bar_picks};
use crate::beam::{assemble_beam, beam_picks};
use crate::config::Config;
use crate::contacts::{assemble_contacts, bar_ctx, beam_ctx, contact_documents, contact_picks};
use crate::doc::{bad, val, Class, Doc, Form, Table};
use crate::oscillator::oscillator_documents;
use crate::pools::{form, maybe, output_entries, pick};
use proptest::prelude::*;
use proptest::sample::Index;
use proptest::strategy::BoxedStrategy;

/// Scene documents from the grammar, with what the reader must answer: one
/// in four may hold wrong types, unknown or duplicate keys (which stop the
/// reader at parsing), the others only values of the right type; one in
/// five is an `[oscillator]` scene (the `oscillator` module).
pub fn documents(cfg: Config) -> BoxedStrategy<Doc> {
    prop_oneof![6 => documents_with(cfg, 0), 2 => documents_with(cfg, 1), 2 => contact_documents(cfg), 2 => oscillator_documents(0), 1 => oscillator_documents(1)].boxed()
}

/// Documents; `tw` is the weight of wrong-type options (0: none).
pub(crate) fn documents_with(cfg: Config, tw: u32) -> BoxedStrategy<Doc> {
    let rare = if tw > 0 { 0.1 } else { 0.0 };
    // Which of [bar] / [beam]: one (mostly), both, or none.
    let which = prop_oneof![10 => Just((true, false)), 10 => Just((false, true)), 1 => Just((true, true)), 1 => Just((false, false))];
    (
        which,
        bar_picks(cfg, tw),
        beam_picks(cfg, tw),
        (maybe(0.5, output_entries(tw)), form(), form(), form()),
        (maybe(rare, pick(&["foo", "Bar", "outputs", "bar.extra"])), maybe(rare, any::<Index>().boxed()), any::<bool>(), any::<Index>()),
        contact_picks(tw, 0.25, 0.15),
    )
        .prop_map(move |((has_bar, has_beam), bar, beam, (output, f_bar, f_beam, f_out), (unknown_table, duplicate, crlf, order), contacts)| {
            let mut tables = Vec::new();
            let mut structure = Vec::new();
            let mut known = Vec::new();
            let mut length = 1.0;
            // The contacts go with the bar (also with both tables: refused anyway) or the beam.
            let ctx = if has_beam && !has_bar { beam_ctx(&beam) } else { bar_ctx(&bar) };
            let (stop_tables, obstacle_table, contact_classes) = assemble_contacts(contacts, &ctx);
            structure.extend(contact_classes);
            if let Some(t) = obstacle_table {
                tables.push(t);
            }
            if has_bar {
                let (entries, s, k, l) = assemble_bar(bar);
                structure.extend(s);
                known = k;
                length = l;
                tables.push(Table { name: "bar".into(), entries, form: f_bar });
            }
            if has_beam {
                let entries = assemble_beam(beam, cfg);
                tables.push(Table { name: "beam".into(), entries, form: f_beam });
            }
            if has_bar == has_beam {
                structure.push(bad(&["bar/beam"]));
                known.clear();
            }
            if let Some(entries) = output {
                tables.push(Table { name: "output".into(), entries, form: f_out });
            }
            if let Some(name) = unknown_table {
                structure.push(Class::Type);
                tables.push(Table { name: name.into(), entries: vec![("x".into(), val("1", Class::Good))], form: Form::Header });
            }
            // A duplicate key (TOML forbids it).
            if let Some(i) = duplicate {
                let all: Vec<(usize, usize)> = tables.iter().enumerate().flat_map(|(t, tab)| (0..tab.entries.len()).map(move |e| (t, e))).collect();
                if !all.is_empty() {
                    let (t, e) = all[i.index(all.len())];
                    let copy = tables[t].entries[e].clone();
                    tables[t].entries.push(copy);
                    structure.push(Class::Type);
                }
            }
            if tables.len() > 1 {
                let k = order.index(tables.len());
                tables.rotate_left(k);
            }
            // The stops after the rotation: their order is their index.
            tables.extend(stop_tables);
            Doc { tables, structure, known_fields: known, length, crlf }
        })
        .boxed()
}
