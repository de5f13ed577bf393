//! Blocks of the single-scale linear stage (METHOD §4, §11): which substructures march together
//! through one factor, and their march. The triangular solves of S are bound by reading the
//! factor from memory, so the right-hand sides of several substructures that share one
//! factorization (identical cells of a granular material, or one substructure of several
//! configurations of a batch) cost far less solved in one pass than one at a time.
//!
//! On windows shorter than the whole interval every substructure marches: the members of one
//! class of operators (over every configuration of a batch) are cut into blocks of a width that
//! depends only on the class's size over the whole problem ([`block_width`]), and every step of
//! a block solves exactly that many columns, zero columns padding a block with fewer members.
//! A column's solution depends on the width of its block only (not on its place or its
//! neighbours), so a run distributed over ranks, each holding part of a class, gives the answer
//! of the threaded run bit for bit. Over the whole interval the skip cache replays the
//! substructures whose inputs did not change, which no rank can know of another's: there each
//! substructure marches alone, with the same substructure of the batch's other configurations.
//! A replay of the converged fields ([`crate::post::replay_blocks`]) marches in the blocks of the
//! solve's linear stage, so that it gives that stage's fields bit for bit.

use super::linear::{BatchInput, SingleScaleSub};
use crate::linalg::factor::{CholeskyFactor, SolveScratch};
use crate::macro_scale::operator_classes::Classes;
use crate::par;
use crate::stages::indicator::IndicatorSums;
use crate::stages::linear_stage::{add_guess, complete, form_rhs, LinearWork};
use crate::state::TraceHistory;

/// The widest block: past it a column costs little less and the blocks get too few to share
/// the cores.
const MAX_WIDTH: usize = 16;

/// One substructure of one configuration in a block: the configuration, the substructure, its
/// buffers and its s_new.
pub(super) type Member<'a> = (usize, usize, &'a mut SingleScaleSub, &'a mut TraceHistory);

/// The width of the blocks of a class of `members` substructure marches (over the whole
/// problem): as even as possible, at most [`MAX_WIDTH`].
pub(super) fn block_width(members: usize) -> usize {
    let blocks = members.div_ceil(MAX_WIDTH).max(1);
    members.div_ceil(blocks).max(1)
}

/// `members` cut into consecutive blocks of `width`.
fn in_blocks<T>(members: Vec<T>, width: usize) -> Vec<Vec<T>> {
    let mut members = members.into_iter().peekable();
    let mut blocks = Vec::new();
    while members.peek().is_some() {
        blocks.push(members.by_ref().take(width).collect());
    }
    blocks
}

/// The substructures `held` cut into the blocks a lone configuration marches in, with their
/// width: each alone over the whole interval with the skip cache (`alone`), else each class's
/// in index order.
pub(crate) fn class_blocks(
    classes: &Classes,
    held: impl Fn(usize) -> bool,
    alone: bool,
) -> Vec<(usize, Vec<usize>)> {
    if alone {
        return (0..classes.of.len())
            .filter(|&i| held(i))
            .map(|i| (1, vec![i]))
            .collect();
    }
    let mut size = vec![0usize; classes.count()];
    let mut by_class: Vec<Vec<usize>> = vec![Vec::new(); classes.count()];
    for (i, &c) in classes.of.iter().enumerate() {
        size[c] += 1;
        if held(i) {
            by_class[c].push(i);
        }
    }
    by_class
        .into_iter()
        .enumerate()
        .flat_map(|(c, members)| {
            let width = block_width(size[c]);
            in_blocks(members, width)
                .into_iter()
                .map(move |b| (width, b))
        })
        .collect()
}

/// Solves the right-hand sides of `works` in place in one pass through `factor`, `columns`
/// wide (zero columns padding; one column: in place with the work's own scratch), through the
/// buffers `block` and `scratch`.
pub(crate) fn solve_together<'w>(
    factor: &CholeskyFactor,
    works: impl Iterator<Item = &'w mut LinearWork>,
    columns: usize,
    block: &mut Vec<f64>,
    scratch: &mut Option<SolveScratch>,
) {
    let mut works: Vec<&mut LinearWork> = works.collect();
    if columns == 1 {
        if let Some(w) = works.first_mut() {
            w.solve_in_place(factor);
        }
        return;
    }
    let n = factor.n();
    block.resize(n * columns, 0.0);
    for (col, w) in works.iter_mut().enumerate() {
        block[col * n..(col + 1) * n].copy_from_slice(w.rhs_mut());
    }
    block[works.len() * n..].iter_mut().for_each(|x| *x = 0.0);
    let scratch = scratch.get_or_insert_with(|| factor.scratch_for(columns));
    factor.solve_columns_in_place(block, columns, scratch);
    for (col, w) in works.iter_mut().enumerate() {
        w.rhs_mut().copy_from_slice(&block[col * n..(col + 1) * n]);
    }
}

/// Marches every substructure of every configuration of `stages` (with `inputs`, writing
/// `outs`) over its window in the blocks of the module doc, in parallel.
pub(super) fn march_all(
    stages: &mut [&mut super::linear::SingleScale],
    inputs: &[BatchInput<'_>],
    outs: &mut [&mut [TraceHistory]],
) {
    let Some(first) = inputs.first() else {
        return;
    };
    let (subs, classes) = (first.ops.subs.len(), first.ops.classes);
    let windowed = inputs.iter().filter(|b| !b.whole).count();
    let mut size = vec![0usize; classes.count()];
    for &c in &classes.of {
        size[c] += 1;
    }
    let mut by_sub: Vec<Vec<Member<'_>>> = (0..subs).map(|_| Vec::new()).collect();
    let mut by_class: Vec<Vec<Member<'_>>> = (0..classes.count()).map(|_| Vec::new()).collect();
    for (c, (stage, out)) in stages.iter_mut().zip(outs.iter_mut()).enumerate() {
        let input = &inputs[c];
        for (i, (b, o)) in stage.subs.iter_mut().zip(out.iter_mut()).enumerate() {
            if !input.ops.distribution.holds_sub(i) {
                continue;
            }
            if input.whole {
                by_sub[i].push((c, i, b, o));
            } else {
                by_class[classes.of[i]].push((c, i, b, o));
            }
        }
    }
    let mut blocks: Vec<(Option<usize>, Vec<Member<'_>>)> = by_sub
        .into_iter()
        .filter(|m| !m.is_empty())
        .map(|m| (None, m))
        .collect();
    for (class, members) in by_class.into_iter().enumerate() {
        let width = block_width(size[class] * windowed);
        blocks.extend(
            in_blocks(members, width)
                .into_iter()
                .map(|b| (Some(width), b)),
        );
    }
    par::for_each_mut(&mut blocks, |_, (width, members)| {
        march_block(members, *width, inputs)
    });
}

/// The members of one block over their windows, step by step: their right-hand sides of a step
/// solved in one pass through their shared factor, `width` columns (None: as many as march that
/// step). Members whose skip cache replays them take no column.
fn march_block(members: &mut [Member<'_>], width: Option<usize>, inputs: &[BatchInput<'_>]) {
    let Some(&(c0, i0, _, _)) = members.first() else {
        return;
    };
    let factor = inputs[c0].ops.factor(i0);
    let mut marching = Vec::with_capacity(members.len());
    for (j, (c, i, b, out)) in members.iter_mut().enumerate() {
        let input = &inputs[*c];
        let sub = &input.ops.subs[*i];
        if input.whole {
            if let Some(sums) = b.skip.replay(sub, input.lin.hats, &mut b.work, out) {
                b.sums = sums;
                b.skipped = true;
                continue;
            }
        }
        // the march writes the work's state from the start's first step on (no copy): both
        // were made for the solver's one time scheme (a new scheme makes new works)
        debug_assert_eq!(b.work.state.ka.len(), input.starts[*i].ka.len());
        b.sums = IndicatorSums::default();
        b.skipped = false;
        marching.push(j);
    }
    let length = |c: usize| inputs[c].lin.steps.1 + 1 - inputs[c].lin.steps.0;
    let longest = marching
        .iter()
        .map(|&j| length(members[j].0))
        .max()
        .unwrap_or(0);
    let mut block = Vec::new();
    let mut scratch: Option<SolveScratch> = None;
    let mut now = vec![false; members.len()];
    for step in 0..longest {
        let mut count = 0;
        for &j in &marching {
            now[j] = step < length(members[j].0);
            count += usize::from(now[j]);
        }
        for (j, (c, i, b, _)) in members.iter_mut().enumerate() {
            if now[j] {
                let input = &inputs[*c];
                let m = input.lin.steps.0 + step;
                // the first step reads the window's start, which the work's state then replaces
                let prev = (step == 0).then(|| &input.starts[*i]);
                form_rhs(&input.ops.subs[*i], &mut b.work, &input.lin, m, prev);
            }
        }
        // one pass through the factor for every member marching this step
        let columns = width.unwrap_or(count).max(count);
        let works = members
            .iter_mut()
            .enumerate()
            .filter(|(j, _)| now[*j])
            .map(|(_, member)| &mut member.2.work);
        solve_together(factor, works, columns, &mut block, &mut scratch);
        for (j, (c, i, b, out)) in members.iter_mut().enumerate() {
            if now[j] {
                add_guess(&mut b.work);
                let input = &inputs[*c];
                let m = input.lin.steps.0 + step;
                let prev = (step == 0).then(|| &input.starts[*i]);
                let sub = &input.ops.subs[*i];
                let sums = complete(sub, &mut b.work, &input.lin, m, out, None, prev);
                b.sums.add(sums);
            }
        }
    }
    for &j in &marching {
        let (c, i, b, out) = &mut members[j];
        let input = &inputs[*c];
        if input.whole {
            b.skip
                .store(&input.ops.subs[*i], input.lin.hats, &b.work, out, b.sums);
        } else {
            b.skip.clear();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_are_as_even_as_possible_and_at_most_the_widest() {
        assert_eq!(block_width(1), 1);
        assert_eq!(block_width(5), 5);
        assert_eq!(block_width(16), 16);
        assert_eq!(block_width(17), 9);
        assert_eq!(block_width(40), 14);
        assert_eq!(block_width(300), 16);
        assert_eq!(block_width(33), 11);
        for m in 1..200 {
            let w = block_width(m);
            assert!(w <= MAX_WIDTH && m.div_ceil(w) == m.div_ceil(MAX_WIDTH));
        }
    }
}
