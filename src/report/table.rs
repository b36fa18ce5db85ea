//! Plain-text tables for the terminal.

/// Render rows as an aligned text table with a header rule.
pub fn text_table(header: &[&str], rows: &[Vec<String>]) -> String {
    let mut w: Vec<usize> = header.iter().map(|h| h.chars().count()).collect();
    for r in rows {
        for (i, c) in r.iter().enumerate() {
            if i < w.len() {
                w[i] = w[i].max(c.chars().count());
            }
        }
    }
    let line = |cells: Vec<String>| -> String {
        let mut s = String::new();
        for (i, c) in cells.iter().enumerate() {
            let pad = w[i].saturating_sub(c.chars().count());
            if i > 0 {
                s.push_str("  ");
            }
            s.push_str(c);
            s.push_str(&" ".repeat(pad));
        }
        s.trim_end().to_string() + "\n"
    };
    let mut out = line(header.iter().map(|s| s.to_string()).collect());
    out.push_str(&line(w.iter().map(|&n| "-".repeat(n)).collect()));
    for r in rows {
        out.push_str(&line(r.clone()));
    }
    out
}

/// One row per unit with every counter (`render`'s counter table).
pub fn counters_table(
    counters: &std::collections::BTreeMap<String, rtl_model::Counters>,
) -> String {
    let rows: Vec<Vec<String>> = counters
        .iter()
        .map(|(name, c)| {
            let mut row = vec![name.clone()];
            row.extend(c.fields().iter().map(|(_, v)| v.to_string()));
            row
        })
        .collect();
    let mut header = vec!["unit"];
    header.extend(
        rtl_model::Counters::default()
            .fields()
            .iter()
            .map(|(k, _)| *k),
    );
    text_table(&header, &rows)
}

/// The elaboration report: each unit elaborated (its gates and RAM bits) or left out
/// (why, and the gates and fragment-clocks that saved).
pub fn elaboration_table(units: &[crate::report::elaboration::Elaborated]) -> String {
    let rows: Vec<Vec<String>> = units
        .iter()
        .map(|e| {
            vec![
                e.name.clone(),
                match &e.left_out {
                    Some(why) => format!("left out: {why}"),
                    None => "elaborated".into(),
                },
                e.summary
                    .as_ref()
                    .map_or(format!("saves {:.0}", e.gates_saved), |s| {
                        format!("{:.0}", s.gates_nand2)
                    }),
                e.summary
                    .as_ref()
                    .map_or(String::new(), |s| s.ram_bits.to_string()),
                if e.left_out.is_some() && e.cycles_saved > 0 {
                    format!("saves {} fragment-clocks", e.cycles_saved)
                } else {
                    String::new()
                },
            ]
        })
        .collect();
    text_table(
        &["unit", "status", "gates_nand2", "ram_bits", "cycles"],
        &rows,
    )
}

/// [`elaboration_table`] with its totals: the chip a frame really elaborated, at the
/// scene's widths (what `render` reports as its one chip).
pub fn chip_elaboration_table(units: &[crate::report::elaboration::Elaborated]) -> String {
    let present: Vec<&rtl_model::UnitSummary> =
        units.iter().filter_map(|e| e.summary.as_ref()).collect();
    let left_out: Vec<_> = units.iter().filter(|e| e.left_out.is_some()).collect();
    format!(
        "{}chip: {} units elaborated at the scene's widths, {:.0} NAND2 gates, {} RAM/ROM bits; left out {} ({:.0} gates saved)\n",
        elaboration_table(units),
        present.len(),
        gate_total(present.iter().map(|s| s.gates_nand2)),
        present.iter().map(|s| s.ram_bits).sum::<u64>(),
        left_out.len(),
        gate_total(left_out.iter().map(|e| e.gates_saved))
    )
}

/// A sum of gate counts that is +0 when there is nothing to add. (`Iterator::sum` of
/// f64 starts from −0.0, which `{:.0}` prints as "-0": "left out 0 (-0 gates saved)".)
pub fn gate_total(gates: impl Iterator<Item = f64>) -> f64 {
    gates.fold(0.0, |total, g| total + g)
}

#[cfg(test)]
mod tests {
    use super::gate_total;

    #[test]
    fn an_empty_gate_total_prints_as_zero_not_minus_zero() {
        let none = gate_total(std::iter::empty());
        assert!(none.is_sign_positive(), "{none}");
        assert_eq!(format!("{none:.0}"), "0");
        assert_eq!(gate_total([1.5, 2.0].into_iter()), 3.5);
    }
}
