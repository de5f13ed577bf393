//! Global node numbering of the undecomposed structure: the two copies of a node on a perfect
//! interface are one node of the assembled mesh (a conforming perfect interface is continuous
//! material), while the two sides of a contact interface stay separate nodes (METHOD §1: one copy
//! per side; §5 contact acts between them).

use lopin_model::error::{LopinError, Result};
use lopin_model::interfaces::interface::Law;
use lopin_model::problem::Problem;

/// Map from (substructure, local node) to the node of the assembled structure.
#[derive(Debug, Clone, PartialEq)]
pub struct Numbering {
    /// `node_of[sub][local node]` = global node.
    pub node_of: Vec<Vec<usize>>,
    /// Number of global nodes.
    pub nodes: usize,
}

impl Numbering {
    /// Merges the node pairs of every perfect interface (union–find), then numbers the classes.
    pub fn new(problem: &Problem) -> Result<Self> {
        let offsets: Vec<usize> = problem
            .subs
            .iter()
            .scan(0, |acc, s| {
                let o = *acc;
                *acc += s.mesh.nodes.len();
                Some(o)
            })
            .collect();
        let total: usize = problem.subs.iter().map(|s| s.mesh.nodes.len()).sum();
        let mut parent: Vec<usize> = (0..total).collect();
        for iface in &problem.interfaces {
            // a non-matching perfect interface is bonded by its pairs, not merged
            if !matches!(iface.law, Law::Perfect) || iface.sides[1].projection.is_some() {
                continue;
            }
            let (s1, s2) = (&iface.sides[0], &iface.sides[1]);
            for (&n1, &n2) in s1.nodes.iter().zip(&s2.nodes) {
                let a = find(&mut parent, offsets[s1.sub] + n1);
                let b = find(&mut parent, offsets[s2.sub] + n2);
                if a != b {
                    parent[a.max(b)] = a.min(b);
                }
            }
        }
        let mut id = vec![usize::MAX; total];
        let mut nodes = 0;
        let mut node_of = Vec::with_capacity(problem.subs.len());
        for (s, sub) in problem.subs.iter().enumerate() {
            let mut map = Vec::with_capacity(sub.mesh.nodes.len());
            for n in 0..sub.mesh.nodes.len() {
                let root = find(&mut parent, offsets[s] + n);
                if id[root] == usize::MAX {
                    id[root] = nodes;
                    nodes += 1;
                }
                map.push(id[root]);
            }
            node_of.push(map);
        }
        let numbering = Self { node_of, nodes };
        numbering.check_initial_velocities(problem)?;
        Ok(numbering)
    }

    /// Number of global dofs.
    pub fn dofs(&self) -> usize {
        3 * self.nodes
    }

    /// Global dof of a substructure dof.
    pub fn dof(&self, sub: usize, local_dof: usize) -> usize {
        3 * self.node_of[sub][local_dof / 3] + local_dof % 3
    }

    /// Global initial velocity field v₀.
    pub fn initial_velocity(&self, problem: &Problem) -> Vec<f64> {
        let mut v = vec![0.0; self.dofs()];
        for (s, sub) in problem.subs.iter().enumerate() {
            for &g in &self.node_of[s] {
                for c in 0..3 {
                    v[3 * g + c] = sub.initial_velocity[c];
                }
            }
        }
        v
    }

    /// A merged node must start with one velocity: two substructures bonded by a perfect
    /// interface with different initial velocities are not one continuous body at t₀.
    fn check_initial_velocities(&self, problem: &Problem) -> Result<()> {
        let mut first: Vec<Option<usize>> = vec![None; self.nodes];
        for (s, sub) in problem.subs.iter().enumerate() {
            for &g in &self.node_of[s] {
                match first[g] {
                    None => first[g] = Some(s),
                    Some(o) if problem.subs[o].initial_velocity != sub.initial_velocity => {
                        return Err(LopinError::Reference(format!(
                            "substructures `{}` and `{}` are bonded by a perfect interface but start with different velocities",
                            problem.subs[o].name, sub.name
                        )));
                    }
                    Some(_) => {}
                }
            }
        }
        Ok(())
    }
}

fn find(parent: &mut [usize], mut x: usize) -> usize {
    while parent[x] != x {
        parent[x] = parent[parent[x]];
        x = parent[x];
    }
    x
}
