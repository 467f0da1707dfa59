//! What a glTF file must be before a rig is read from it: its nodes a set of disjoint trees, and
//! every accessor the hand reads of the type it holds and within its buffer. A hostile-input
//! probe (2026-12-03) found a node that is its own child hanging the reader, a node reached
//! along two paths at each of 40 levels walked 2⁴⁰ times, a stride shorter than its element
//! and indices of floats panicking inside the glTF reader, and an index view past its buffer
//! read as "no indices" (consecutive vertices taken as triangles).

use gltf::accessor::{DataType, Dimensions};

/// The node hierarchy is a set of trees: no node has two parents, none is its own ancestor.
pub fn check_hierarchy(doc: &gltf::Document, file: &str) -> Result<(), String> {
    let nodes: Vec<gltf::Node> = doc.nodes().collect();
    let count = nodes.len();
    let name = |n: usize| {
        nodes[n]
            .name()
            .map(|s| format!(" (\"{s}\")"))
            .unwrap_or_default()
    };
    let mut parent: Vec<Option<usize>> = vec![None; count];
    for node in &nodes {
        for child in node.children() {
            let c = child.index();
            if let Some(p) = parent[c] {
                return Err(format!(
                    "\"{file}\": node {c}{} is a child of node {p} and of node {}: a glTF node has \
                     one parent at most (its nodes are a set of trees)",
                    name(c),
                    node.index()
                ));
            }
            parent[c] = Some(node.index());
        }
    }
    // With one parent each, a walk from the roots meets every node once; those it misses lie
    // on a cycle.
    let mut reached = vec![false; count];
    let mut stack: Vec<usize> = (0..count).filter(|&n| parent[n].is_none()).collect();
    while let Some(n) = stack.pop() {
        reached[n] = true;
        stack.extend(nodes[n].children().map(|c| c.index()));
    }
    if let Some(n) = reached.iter().position(|r| !r) {
        return Err(format!(
            "\"{file}\": node {n}{} is its own ancestor (its children lead back to it): a glTF \
             node hierarchy is a set of trees",
            name(n)
        ));
    }
    Ok(())
}

/// `accessor`, which the hand reads as `what`, holds one of `types` and lies within its buffer
/// view and the view within its buffer (`buffers`: the bytes read), with a stride no shorter
/// than its element — its sparse substitutes' views too.
pub fn check_accessor(
    accessor: &gltf::Accessor,
    what: &str,
    types: &[(DataType, Dimensions)],
    buffers: &[Vec<u8>],
    file: &str,
) -> Result<(), String> {
    let i = accessor.index();
    let (data, dims) = (accessor.data_type(), accessor.dimensions());
    if !types.contains(&(data, dims)) {
        let wanted: Vec<String> = types
            .iter()
            .map(|(d, m)| format!("{m:?} of {d:?}"))
            .collect();
        return Err(format!(
            "\"{file}\": accessor {i} ({what}) holds {dims:?} of {data:?}; the hand reads {}",
            wanted.join(" or ")
        ));
    }
    let element = accessor.size();
    let at = |detail: String| format!("\"{file}\": accessor {i} ({what}): {detail}");
    if let Some(view) = accessor.view() {
        let stride = view_range(&view, element, buffers).map_err(at)?;
        let needed = span(accessor.offset(), accessor.count(), stride, element);
        if needed.is_none_or(|end| end > view.length()) {
            return Err(at(format!(
                "{} elements of {element} bytes from byte {} of bufferView {} run past its {} bytes",
                accessor.count(),
                accessor.offset(),
                view.index(),
                view.length()
            )));
        }
    }
    if let Some(sparse) = accessor.sparse() {
        let n = sparse.count();
        let (indices, values) = (sparse.indices(), sparse.values());
        let index_size = indices.index_type().size();
        for (view, offset, size, part) in [
            (
                indices.view(),
                indices.offset(),
                index_size,
                "sparse indices",
            ),
            (values.view(), values.offset(), element, "sparse values"),
        ] {
            view_range(&view, size, buffers).map_err(at)?;
            if span(offset, n, size, size).is_none_or(|end| end > view.length()) {
                return Err(at(format!(
                    "its {part} ({n} of {size} bytes from byte {offset}) run past bufferView {}'s \
                     {} bytes",
                    view.index(),
                    view.length()
                )));
            }
        }
    }
    Ok(())
}

/// The view's stride (its element's size when packed), checked against `element` and against
/// the glTF rules (a multiple of 4 from 4 to 252), and the view within its buffer.
fn view_range(
    view: &gltf::buffer::View,
    element: usize,
    buffers: &[Vec<u8>],
) -> Result<usize, String> {
    let v = view.index();
    let stride = view.stride().unwrap_or(element);
    if view.stride().is_some() && (stride < element || !stride.is_multiple_of(4) || stride > 252) {
        return Err(format!(
            "bufferView {v}'s byteStride {stride} does not hold its {element}-byte elements (a \
             stride is at least the element, a multiple of 4, at most 252)"
        ));
    }
    let b = view.buffer().index();
    let held = buffers.get(b).map_or(0, Vec::len);
    let end = view.offset().checked_add(view.length());
    if end.is_none_or(|end| end > held) {
        return Err(format!(
            "bufferView {v} runs from byte {} for {} bytes, past the {held} bytes of buffer {b} \
             (a buffer cut short, or a view that does not fit it)",
            view.offset(),
            view.length()
        ));
    }
    Ok(stride)
}

/// Where `count` elements of `element` bytes, `stride` apart from byte `offset`, end (`None` on
/// overflow).
fn span(offset: usize, count: usize, stride: usize, element: usize) -> Option<usize> {
    if count == 0 {
        return Some(offset);
    }
    (count - 1)
        .checked_mul(stride)?
        .checked_add(element)?
        .checked_add(offset)
}

/// A joint farther from the wrist than this many times the median joint's distance lies off
/// the hand (a fingertip is about 2.5 times the median: the metacarpal heads lie halfway).
const OUTLIER: f64 = 20.0;

/// Each digit's joints, from the wrist out, ever farther from the wrist and apart: two joints
/// at one point (one node named for both, or a transform collapsing a direction) or a chain
/// named backwards made a lattice whose bones held no flesh, told as a resolution too coarse;
/// and no joint far off the others (a node's transform off by a huge translation or scale).
/// `node(key)`: the name of the node a joint was read from.
pub fn check_chains(
    joints: &std::collections::BTreeMap<String, nalgebra::Vector3<f64>>,
    node: &dyn Fn(&str) -> String,
    file: &str,
) -> Result<(), String> {
    let Some(wrist) = joints.get("wrist") else {
        return Ok(());
    };
    // A hand's length scale: the wrist to the farthest joint.
    let reach = joints
        .values()
        .map(|p| (p - wrist).norm())
        .fold(0.0, f64::max);
    // One joint far beyond the others (a node's transform off by a huge translation or
    // scale) makes that length scale meaningless: told as such, naming it.
    let mut distances: Vec<(f64, &String)> = joints
        .iter()
        .filter(|(k, _)| k.as_str() != "wrist")
        .map(|(k, p)| ((p - wrist).norm(), k))
        .collect();
    distances.sort_by(|a, b| a.0.total_cmp(&b.0));
    if let (Some(&(median, _)), Some(&(farthest, key))) =
        (distances.get(distances.len() / 2), distances.last())
    {
        if median > 0.0 && farthest > OUTLIER * median {
            return Err(format!(
                "\"{file}\": joint {key} (node \"{}\") lies {:.3e} mm from the wrist, {:.3e} \
                 times as far as the hand's joints lie from it (median {:.3e} mm): its node's \
                 transform (or a parent's) moves or scales it far off the hand",
                crate::util::shown(&node(key)),
                farthest * 1e3,
                farthest / median,
                median * 1e3
            ));
        }
    }
    let keys = crate::hand::rig_names::joint_keys();
    let digit = |k: &str| k.split('.').next().unwrap_or("").to_string();
    let mut previous: Option<&str> = None;
    for key in keys.iter().skip(1) {
        let Some(p) = joints.get(key) else {
            continue;
        };
        if let Some(before) = previous.filter(|b| digit(b) == digit(key)) {
            let q = joints[before];
            let apart = (p - q).norm();
            let (near, far) = ((q - wrist).norm(), (p - wrist).norm());
            if apart < 0.01 * reach {
                return Err(format!(
                    "\"{file}\": joints {before} (node \"{}\") and {key} (node \"{}\") lie {:.3} mm \
                     apart: a hand's joints are millimetres apart (is one node named for both, or \
                     does a transform collapse them, a zero scale?)",
                    crate::util::shown(&node(before)),
                    crate::util::shown(&node(key)),
                    apart * 1e3
                ));
            }
            if far <= near {
                return Err(format!(
                    "\"{file}\": joint {key} (node \"{}\") is {:.1} mm from the wrist, no farther \
                     than {before} (node \"{}\", {:.1} mm): a digit's joints run out from the \
                     wrist (are its nodes named in reverse?)",
                    crate::util::shown(&node(key)),
                    far * 1e3,
                    crate::util::shown(&node(before)),
                    near * 1e3
                ));
            }
        }
        previous = Some(key);
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::{check_chains, span};
    use nalgebra::Vector3;
    use std::collections::BTreeMap;

    /// A hand's joints: each digit along its own direction from the wrist, 20 mm apart.
    fn joints() -> BTreeMap<String, Vector3<f64>> {
        let mut out = BTreeMap::new();
        out.insert("wrist".to_string(), Vector3::zeros());
        for key in crate::hand::rig_names::joint_keys().into_iter().skip(1) {
            let digit = ["thumb", "index", "middle", "ring", "little"]
                .iter()
                .position(|d| key.starts_with(d))
                .unwrap() as f64;
            let k = ["metacarpal", "proximal", "middle", "distal", "tip"]
                .iter()
                .position(|p| key.ends_with(p))
                .unwrap() as f64;
            let direction = Vector3::new(1.0, 0.2 * (digit - 2.0), 0.0).normalize();
            out.insert(key, direction * 0.02 * (k + 1.0));
        }
        out
    }

    #[test]
    fn a_joint_far_off_the_hand_is_named_as_such_and_collapsed_ones_as_collapsed() {
        let node = |k: &str| format!("node of {k}");
        assert!(check_chains(&joints(), &node, "hand.glb").is_ok());
        // The index tip moved 1e30 m away: named as far off, not as collapsed.
        let mut far = joints();
        far.insert("index.tip".into(), Vector3::new(1e30, 0.0, 0.0));
        let e = check_chains(&far, &node, "hand.glb").unwrap_err();
        assert!(
            e.contains("joint index.tip (node \"node of index.tip\") lies 1.000e33 mm")
                && e.contains("far off the hand"),
            "{e}"
        );
        // Two joints at one point: collapsed.
        let mut collapsed = joints();
        let at = collapsed["middle.proximal"];
        collapsed.insert("middle.middle".into(), at);
        let e = check_chains(&collapsed, &node, "hand.glb").unwrap_err();
        assert!(e.contains("lie 0.000 mm apart"), "{e}");
    }

    #[test]
    fn spans_end_where_the_last_element_ends_and_overflow_is_none() {
        assert_eq!(span(8, 3, 16, 12), Some(8 + 2 * 16 + 12));
        assert_eq!(span(0, 0, 12, 12), Some(0));
        assert_eq!(span(0, usize::MAX, 12, 12), None);
    }
}
