//! Dealing substructures to the ranks of a distributed run (`core/src/distributed/rank_assignment.rs`):
//! on `granular-small` (64 substructures) and `two-blocks --split 5` (50), for 1 to 8 ranks,
//! every substructure has one rank, the loads add up to the problem, the largest rank holds at
//! most 1.25 times the mean dofs, and METIS cuts fewer trace entries between ranks than dealing
//! the substructures round-robin (the naive assignment). Measured: `granular-small` on 4 ranks
//! 3,072 trace entries cut against 4,608 round-robin, on 8 ranks 4,608 against 9,216;
//! `two-blocks --split 5` on 4 ranks 2,646 against 9,990 (largest rank 1.04× the mean dofs).

use lopin_core::distributed::rank_assignment::assign;
use lopin_core::macro_scale::operator_classes::factor_classes;
use lopin_core::scene;

#[test]
fn ranks_get_balanced_work_and_few_cut_interfaces() {
    let mut blocks = scene::registry::builtin("two-blocks").expect("scene");
    blocks.split(5).expect("split");
    for spec in [
        scene::registry::builtin("granular-small").expect("scene"),
        blocks,
    ] {
        let problem = scene::problem_of(&spec, &spec.name).expect("builds");
        let classes = factor_classes(&problem.subs);
        let dofs: usize = problem.subs.iter().map(|s| s.ndof()).sum();
        for ranks in [1, 2, 3, 4, 8] {
            let a = assign(&problem, &classes.of, ranks).expect("assigns");
            assert_eq!(a.rank_of.len(), problem.subs.len());
            assert!(a.rank_of.iter().all(|&r| r < ranks));
            assert_eq!(a.loads.iter().map(|l| l.dofs).sum::<usize>(), dofs);
            assert_eq!(
                a.loads.iter().map(|l| l.substructures).sum::<usize>(),
                problem.subs.len()
            );
            let naive: usize = problem
                .interfaces
                .iter()
                .filter(|i| i.sides.len() == 2 && i.sides[0].sub % ranks != i.sides[1].sub % ranks)
                .map(|i| 2 * i.len)
                .sum();
            let cut: usize = a.loads.iter().map(|l| l.cut_entries).sum();
            println!(
                "{} on {ranks} ranks: largest {:.3}x mean dofs, {} interfaces cut, {cut} trace \
                 entries cut (round-robin {naive}), factorizations per rank {:?}",
                spec.name,
                a.dof_imbalance(),
                a.cut_interfaces(),
                a.loads.iter().map(|l| l.factorizations).collect::<Vec<_>>()
            );
            assert!(a.dof_imbalance() <= 1.25, "{ranks}: {:?}", a.loads);
            if ranks == 1 {
                assert_eq!(cut, 0);
            } else {
                assert!(cut < naive, "{ranks} ranks: {cut} against {naive}");
            }
        }
        let e = assign(&problem, &classes.of, problem.subs.len() + 1)
            .expect_err("more ranks than substructures");
        assert!(e.contains("at most one rank per substructure"), "{e}");
    }
}
