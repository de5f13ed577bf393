//! A stored configuration's picture, kept compactly (f32, half the memory of the f64 fields):
//! the nodal fields of one time step (displacement, velocity, von Mises stress) and the contact
//! histories of every step, enough to draw the 3D view and the contact plot of that
//! configuration at once, without the solver. Built from and turned back into the
//! [`StepFields`] and [`ContactHistory`] the rest of the explorer draws.

use crate::fields::{StepFields, SubStepFields};
use lopin_core::post::ContactHistory;

/// Nodal fields of one substructure, f32.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
struct SubPicture {
    u: Vec<f32>,
    v: Vec<f32>,
    von_mises: Vec<f32>,
}

/// One contact interface's history, f32; tables flattened step-major (`nodes` per step).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
struct ContactPicture {
    interface: usize,
    nodes: usize,
    pressure: Vec<f32>,
    gap: Vec<f32>,
    slip: Vec<f32>,
    normal_force: Vec<f32>,
}

/// The picture of one configuration at one time step.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Picture {
    /// The time step of the nodal fields.
    pub step: usize,
    subs: Vec<SubPicture>,
    contact: Vec<ContactPicture>,
}

fn narrow(x: &[f64]) -> Vec<f32> {
    x.iter().map(|&v| v as f32).collect()
}

fn widen(x: &[f32]) -> Vec<f64> {
    x.iter().map(|&v| f64::from(v)).collect()
}

fn flat(table: &[Vec<f64>]) -> Vec<f32> {
    table.iter().flatten().map(|&v| v as f32).collect()
}

fn table(flat: &[f32], nodes: usize) -> Vec<Vec<f64>> {
    if nodes == 0 {
        return vec![Vec::new(); flat.len()];
    }
    flat.chunks(nodes).map(widen).collect()
}

impl Picture {
    /// The picture of converged fields at one step and the contact histories of the same
    /// solution.
    pub fn of(fields: &StepFields, contact: &[ContactHistory]) -> Picture {
        Picture {
            step: fields.step,
            subs: fields
                .subs
                .iter()
                .map(|s| SubPicture {
                    u: narrow(&s.u),
                    v: narrow(&s.v),
                    von_mises: narrow(&s.von_mises),
                })
                .collect(),
            contact: contact
                .iter()
                .map(|h| ContactPicture {
                    interface: h.interface,
                    nodes: h.pressure.first().map_or(0, Vec::len),
                    pressure: flat(&h.pressure),
                    gap: flat(&h.gap),
                    slip: flat(&h.slip),
                    normal_force: narrow(&h.normal_force),
                })
                .collect(),
        }
    }

    /// The nodal fields, as fields of `generation` (`live`: drawn as a stand-in while a solve
    /// refines them).
    pub fn fields(&self, generation: u64, live: bool) -> StepFields {
        StepFields {
            generation,
            step: self.step,
            live,
            subs: self
                .subs
                .iter()
                .map(|s| SubStepFields {
                    u: widen(&s.u),
                    v: widen(&s.v),
                    von_mises: widen(&s.von_mises),
                })
                .collect(),
        }
    }

    /// The contact histories.
    pub fn contact(&self) -> Vec<ContactHistory> {
        self.contact
            .iter()
            .map(|c| ContactHistory {
                interface: c.interface,
                pressure: table(&c.pressure, c.nodes),
                gap: table(&c.gap, c.nodes),
                slip: table(&c.slip, c.nodes),
                normal_force: widen(&c.normal_force),
            })
            .collect()
    }

    /// Bytes of stored values.
    pub fn bytes(&self) -> usize {
        let subs: usize = self
            .subs
            .iter()
            .map(|s| s.u.len() + s.v.len() + s.von_mises.len())
            .sum();
        let contact: usize = self
            .contact
            .iter()
            .map(|c| c.pressure.len() + c.gap.len() + c.slip.len() + c.normal_force.len())
            .sum();
        4 * (subs + contact)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_picture_gives_back_its_fields_and_histories_to_f32_precision() {
        let fields = StepFields {
            generation: 3,
            step: 7,
            live: false,
            subs: vec![SubStepFields {
                u: vec![1e-6, -2e-6, 1.0 / 3.0],
                v: vec![0.5, 0.25, -1.0],
                von_mises: vec![2.5e8],
            }],
        };
        let contact = vec![ContactHistory {
            interface: 2,
            pressure: vec![vec![1.0, 2.0], vec![3.0, 4.0]],
            gap: vec![vec![0.0, 0.5], vec![0.0, 0.0]],
            slip: vec![vec![0.0, 0.0], vec![0.25, 0.125]],
            normal_force: vec![10.0, 20.0],
        }];
        let p = Picture::of(&fields, &contact);
        assert_eq!(p.bytes(), 4 * (7 + 2 * 3 * 2 + 2));
        let back = p.fields(9, true);
        assert_eq!((back.generation, back.step, back.live), (9, 7, true));
        let (a, b) = (&back.subs[0], &fields.subs[0]);
        for (x, y) in a.u.iter().chain(&a.v).zip(b.u.iter().chain(&b.v)) {
            assert!((x - y).abs() <= 1e-7 * y.abs(), "{x} vs {y}");
        }
        assert_eq!(a.von_mises, vec![2.5e8]);
        assert_eq!(p.contact(), contact);
    }
}
