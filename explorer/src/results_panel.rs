//! The opened result folder as the UI sees it and its section of the left panel: the folder,
//! its kind, the table of its configurations (parameter values, quantities of interest,
//! iterations) sortable by any column (a click on the header; again to reverse), the row shown,
//! and a plot of one column against the first parameter (one line per value of the others, the
//! map of a two-parameter study read as curves). A click on a row shows that configuration.

use crate::params::{FrictionTargets, Params};
use crate::result_folder::{row_params, FolderKind, ResultTable};
use egui::{Color32, RichText};
use egui_plot::{Legend, Line, Plot, PlotPoints, Points};
use lopin_core::Parameter;
use std::path::PathBuf;

/// Rows drawn before the table scrolls.
const TABLE_HEIGHT: f32 = 190.0;

/// The opened folder's UI state.
#[derive(Debug, Clone)]
pub struct ResultsView {
    /// The folder.
    pub path: PathBuf,
    /// What it holds.
    pub kind: FolderKind,
    /// Its configurations.
    pub table: ResultTable,
    /// The explorer's parameters of the folder's scene as built.
    base: Params,
    /// Sorted by this column ([`ResultTable::cell`] order), ascending or not.
    pub sort: (usize, bool),
    /// The row on screen (the newest shown).
    pub shown: Option<usize>,
    /// The column plotted against the first parameter.
    pub plotted: usize,
}

impl ResultsView {
    /// The view of a folder opened with `first` shown.
    pub fn new(
        path: PathBuf,
        kind: FolderKind,
        table: ResultTable,
        base: Params,
        first: usize,
    ) -> Self {
        let plotted = table.parameters.len().min(table.columns() - 1);
        ResultsView {
            path,
            kind,
            table,
            base,
            sort: (0, true),
            shown: Some(first),
            plotted,
        }
    }

    /// The explorer's parameters of row `r`.
    pub fn params_of(&self, r: usize) -> Params {
        let assigned = self.table.rows.get(r).map_or(&[][..], |r| &r.assigned);
        row_params(&self.base, assigned)
    }

    /// Gives the friction slider's targets the friction values of row `r` (every contact's or
    /// each zone's).
    pub fn give_friction(&self, r: usize, targets: &mut FrictionTargets) {
        let assigned = self.table.rows.get(r).map_or(&[][..], |r| &r.assigned);
        for a in assigned
            .iter()
            .filter(|a| a.parameter == Parameter::Friction)
        {
            targets.set(a.zone, Some(a.value));
        }
    }

    /// What the convergence plot's marker calls row `r`.
    pub fn row_name(&self, r: usize) -> String {
        let Some(row) = self.table.rows.get(r) else {
            return format!("row {r}");
        };
        let values: Vec<String> = self
            .table
            .parameters
            .iter()
            .zip(&row.assigned)
            .map(|(n, a)| format!("{n} = {}", short(a.value)))
            .collect();
        if values.is_empty() {
            format!("{} {}", self.kind.name(), row.name)
        } else {
            format!("{}: {}", row.name, values.join(", "))
        }
    }

    /// The points of the plotted column against the first parameter, one line per value of the
    /// other parameters (sorted along the first).
    pub fn curves(&self) -> Vec<(String, Vec<[f64; 2]>)> {
        let np = self.table.parameters.len();
        if np == 0 {
            return Vec::new();
        }
        let mut lines: Vec<(Vec<u64>, String, Vec<[f64; 2]>)> = Vec::new();
        for (r, row) in self.table.rows.iter().enumerate() {
            let key: Vec<u64> = row
                .assigned
                .iter()
                .skip(1)
                .map(|a| a.value.to_bits())
                .collect();
            let y = self.table.cell(r, self.plotted);
            let x = self.table.cell(r, 0);
            if !(x.is_finite() && y.is_finite()) {
                continue;
            }
            let at = match lines.iter().position(|l| l.0 == key) {
                Some(i) => i,
                None => {
                    let name: Vec<String> = self.table.parameters[1..]
                        .iter()
                        .zip(row.assigned.iter().skip(1))
                        .map(|(n, a)| format!("{n} = {}", short(a.value)))
                        .collect();
                    lines.push((key, name.join(", "), Vec::new()));
                    lines.len() - 1
                }
            };
            lines[at].2.push([x, y]);
        }
        lines
            .into_iter()
            .map(|(_, name, mut pts)| {
                pts.sort_by(|a, b| a[0].total_cmp(&b[0]));
                (name, pts)
            })
            .collect()
    }
}

/// A number as the table writes it.
fn short(v: f64) -> String {
    if !v.is_finite() {
        "–".into()
    } else if v == 0.0 || (1e-3..1e4).contains(&v.abs()) {
        format!("{v:.4}")
    } else {
        format!("{v:.3e}")
    }
}

/// Draws the folder's section; returns the row clicked, if any.
pub fn show(ui: &mut egui::Ui, view: &mut ResultsView) -> Option<usize> {
    let mut clicked = None;
    ui.heading(format!("{} folder", view.kind.name()));
    ui.label(RichText::new(view.path.display().to_string()).weak());
    let names = view.table.column_names();
    let converged = view.table.rows.iter().filter(|r| r.converged).count();
    ui.label(format!(
        "{} configuration{}, {converged} converged",
        view.table.rows.len(),
        if view.table.rows.len() == 1 { "" } else { "s" }
    ));
    let order = view.table.sorted(view.sort.0, view.sort.1);
    egui::ScrollArea::both()
        .id_salt("lopin-results-table")
        .max_height(TABLE_HEIGHT)
        .show(ui, |ui| {
            egui::Grid::new("lopin-results-grid")
                .striped(true)
                .show(ui, |ui| {
                    ui.label("");
                    for (c, name) in names.iter().enumerate() {
                        let arrow = match view.sort {
                            (s, true) if s == c => " (asc)",
                            (s, false) if s == c => " (desc)",
                            _ => "",
                        };
                        if ui.button(format!("{name}{arrow}")).clicked() {
                            view.sort = if view.sort.0 == c {
                                (c, !view.sort.1)
                            } else {
                                (c, true)
                            };
                        }
                    }
                    ui.end_row();
                    for &r in &order {
                        let row = &view.table.rows[r];
                        let selected = view.shown == Some(r);
                        let name = if row.converged {
                            RichText::new(&row.name)
                        } else {
                            RichText::new(&row.name).color(Color32::from_rgb(220, 150, 60))
                        };
                        if ui.selectable_label(selected, name).clicked() {
                            clicked = Some(r);
                        }
                        for c in 0..names.len() {
                            ui.label(short(view.table.cell(r, c)));
                        }
                        ui.end_row();
                    }
                });
        });
    if !view.table.parameters.is_empty() && view.table.rows.len() > 1 {
        egui::ComboBox::from_label(format!("against {}", view.table.parameters[0]))
            .selected_text(names.get(view.plotted).cloned().unwrap_or_default())
            .show_ui(ui, |ui| {
                for (c, name) in names.iter().enumerate().skip(1) {
                    ui.selectable_value(&mut view.plotted, c, name);
                }
            });
        let shown = view
            .shown
            .map(|r| [view.table.cell(r, 0), view.table.cell(r, view.plotted)]);
        let curves = view.curves();
        Plot::new("lopin-results-plot")
            .height(140.0)
            .legend(Legend::default())
            .allow_scroll(false)
            .show(ui, |plot| {
                for (name, pts) in curves {
                    let label = if name.is_empty() {
                        "stored".into()
                    } else {
                        name
                    };
                    plot.line(Line::new(label.clone(), PlotPoints::from(pts.clone())));
                    plot.points(Points::new(label, PlotPoints::from(pts)).radius(2.5));
                }
                if let Some(p) = shown.filter(|p| p[0].is_finite() && p[1].is_finite()) {
                    plot.points(
                        Points::new("shown", PlotPoints::from(vec![p]))
                            .radius(5.0)
                            .color(Color32::from_rgb(240, 200, 60)),
                    );
                }
            });
    }
    clicked
}
