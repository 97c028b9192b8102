//! Reference resolution: every `#n` must be defined, and the reference graph
//! must be acyclic. Both checks are iterative (no recursion on input depth
//! beyond the bounded parameter nesting).
use super::parser::{Instance, StepFile, Value};
use crate::cad::error::{CadError, CadResult};

/// Checks that all references resolve and that no cycle exists.
pub fn check_references(step: &StepFile, file: &str) -> CadResult<()> {
    let adjacency = adjacency(step, file)?;
    find_cycle(step, &adjacency, file)
}

fn collect_refs(value: &Value, out: &mut Vec<u64>) {
    match value {
        Value::Ref(id) => out.push(*id),
        Value::List(items) => items.iter().for_each(|v| collect_refs(v, out)),
        Value::Typed(_, inner) => collect_refs(inner, out),
        _ => {}
    }
}

/// The references of one instance, in order.
pub fn instance_refs(inst: &Instance) -> Vec<u64> {
    let mut out = Vec::new();
    for rec in &inst.records {
        rec.params.iter().for_each(|v| collect_refs(v, &mut out));
    }
    out
}

fn adjacency(step: &StepFile, file: &str) -> CadResult<Vec<Vec<usize>>> {
    let index: std::collections::HashMap<u64, usize> = step
        .instances
        .iter()
        .enumerate()
        .map(|(k, inst)| (inst.id, k))
        .collect();
    let mut adj = Vec::with_capacity(step.instances.len());
    for inst in &step.instances {
        let mut row = Vec::new();
        for target in instance_refs(inst) {
            let Some(&k) = index.get(&target) else {
                return Err(CadError::UnknownReference {
                    file: file.to_string(),
                    line: inst.pos.line,
                    column: inst.pos.column,
                    entity: inst.id,
                    target,
                });
            };
            row.push(k);
        }
        adj.push(row);
    }
    Ok(adj)
}

#[derive(Clone, Copy, PartialEq)]
enum Mark {
    New,
    Active,
    Done,
}

fn find_cycle(step: &StepFile, adj: &[Vec<usize>], file: &str) -> CadResult<()> {
    let mut marks = vec![Mark::New; adj.len()];
    for root in 0..adj.len() {
        if marks.get(root) == Some(&Mark::New) {
            dfs(root, adj, &mut marks)
                .map_or(Ok(()), |path| Err(cycle_error(step, &path, file)))?;
        }
    }
    Ok(())
}

/// Iterative depth-first search; returns the cycle's node path if one is found.
fn dfs(root: usize, adj: &[Vec<usize>], marks: &mut [Mark]) -> Option<Vec<usize>> {
    let mut stack: Vec<(usize, usize)> = vec![(root, 0)];
    set(marks, root, Mark::Active);
    while let Some(&mut (node, ref mut next)) = stack.last_mut() {
        let child = adj.get(node).and_then(|row| row.get(*next)).copied();
        *next += 1;
        match child {
            None => {
                set(marks, node, Mark::Done);
                stack.pop();
            }
            Some(c) => match marks.get(c) {
                Some(Mark::New) => {
                    set(marks, c, Mark::Active);
                    stack.push((c, 0));
                }
                Some(Mark::Active) => return Some(cycle_path(&stack, c)),
                _ => {}
            },
        }
    }
    None
}

fn set(marks: &mut [Mark], k: usize, m: Mark) {
    if let Some(slot) = marks.get_mut(k) {
        *slot = m;
    }
}

fn cycle_path(stack: &[(usize, usize)], back_to: usize) -> Vec<usize> {
    let start = stack.iter().position(|&(n, _)| n == back_to).unwrap_or(0);
    let mut path: Vec<usize> = stack.iter().skip(start).map(|&(n, _)| n).collect();
    path.push(back_to);
    path
}

fn cycle_error(step: &StepFile, path: &[usize], file: &str) -> CadError {
    let inst = path.first().and_then(|&k| step.instances.get(k));
    let names: Vec<String> = path
        .iter()
        .filter_map(|&k| step.instances.get(k))
        .map(|i| format!("#{}", i.id))
        .collect();
    CadError::CyclicReference {
        file: file.to_string(),
        line: inst.map_or(0, |i| i.pos.line),
        column: inst.map_or(0, |i| i.pos.column),
        entity: inst.map_or(0, |i| i.id),
        reason: names.join(" -> "),
    }
}
