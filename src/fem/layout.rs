//! The mesh of the string, element by element: each element's length, its section and the
//! position of every node (MODEL.md §11.5, per-element section properties).
//!
//! Elements of the same section and length share one [`ElementKind`] (the element's matrices and
//! its strain-energy law are computed once per kind); [`ElementLayout::kind`] says which kind an
//! element is. A string of one section on a uniform mesh has one kind, and every operator
//! assembled through the layout is the one of that element repeated, bit for bit.
//!
//! Node 0 is the top drive (x = 0), node N the bit (x = L); element e joins nodes e and e + 1.

use super::{BeamElement, StrainEnergy};
use crate::model::{Drillstring, Section, WallStiffnessPer};

/// One kind of element: a section at one element length.
#[derive(Debug, Clone)]
pub struct ElementKind {
    /// The element (its length and section constants).
    pub element: BeamElement,
    /// The section's strain energy per unit length (constitutive and section data).
    pub strain_law: StrainEnergy,
    /// The index of its section in [`Drillstring::section_strings`] (0 for a string of one).
    pub section: usize,
    /// The section's outer radius R_ext, m (where it touches the wall).
    pub outer_radius: f64,
}

/// The elements of a mesh, top drive to bit.
#[derive(Debug, Clone)]
pub struct ElementLayout {
    kinds: Vec<ElementKind>,
    /// Per element, its index in `kinds`.
    kind_of: Vec<usize>,
    /// x of every node, m (N + 1 values, 0 to L).
    node_x: Vec<f64>,
    /// x of every element's midpoint, m (N values).
    midpoint_x: Vec<f64>,
}

impl ElementLayout {
    /// The uniform mesh of `elements` equal elements along `string` (h = L/N, node i at i h).
    ///
    /// # Panics
    /// If `elements` is 0 (problem validation asks for at least one).
    ///
    /// A string of sections ([`Drillstring::section_strings`]) has one kind per section, each
    /// section cut into equal elements: the `elements` are shared out so that the element
    /// lengths of the sections are as even as they can be (one element at least per section;
    /// [`share_out`]). No element straddles a section boundary.
    ///
    /// # Panics
    /// If `elements` is 0 or below the number of sections (problem validation refuses both).
    pub fn of(string: &Drillstring, elements: usize) -> Self {
        assert!(elements > 0, "a mesh needs at least one element");
        let sections = string.section_strings();
        if let [only] = sections.as_slice() {
            let h = string.length / elements as f64;
            let kind = ElementKind {
                element: BeamElement::new(h, Section::of(only)),
                strain_law: StrainEnergy::of(only),
                section: 0,
                outer_radius: only.pipe.outer_radius,
            };
            return ElementLayout {
                kinds: vec![kind],
                kind_of: vec![0; elements],
                node_x: (0..=elements).map(|i| i as f64 * h).collect(),
                midpoint_x: (0..elements).map(|e| (e as f64 + 0.5) * h).collect(),
            };
        }
        // A graded mesh shares the elements in proportion to the sections' own counts (exactly
        // them when `elements` is their sum, k times them for k times the sum: `verify`'s
        // refined mesh); otherwise by length.
        let weights: Vec<f64> = match (string.sections.iter())
            .map(|s| s.elements)
            .collect::<Option<Vec<usize>>>()
        {
            Some(counts) => counts.iter().map(|&n| n as f64).collect(),
            None => sections.iter().map(|s| s.length).collect(),
        };
        let counts = share_out(elements, &weights);
        let mut layout = ElementLayout {
            kinds: Vec::with_capacity(sections.len()),
            kind_of: Vec::with_capacity(elements),
            node_x: vec![0.0],
            midpoint_x: Vec::with_capacity(elements),
        };
        let mut start = 0.0;
        for (k, (section, &n)) in sections.iter().zip(&counts).enumerate() {
            let h = section.length / n as f64;
            layout.kinds.push(ElementKind {
                element: BeamElement::new(h, Section::of(section)),
                strain_law: StrainEnergy::of(section),
                section: k,
                outer_radius: section.pipe.outer_radius,
            });
            for j in 0..n {
                layout.kind_of.push(k);
                layout.midpoint_x.push(start + (j as f64 + 0.5) * h);
                layout.node_x.push(start + (j + 1) as f64 * h);
            }
            start += section.length;
        }
        layout
    }

    /// The outer radius at node `i`, m: the larger of the elements it joins (a node at a
    /// section boundary touches the wall with the larger pipe).
    pub fn node_outer_radius(&self, i: usize) -> f64 {
        let r = |e: usize| self.kinds[self.kind_of[e]].outer_radius;
        match i {
            0 => r(0),
            i if i == self.elements() => r(i - 1),
            i => r(i - 1).max(r(i)),
        }
    }

    /// Number of elements N.
    pub fn elements(&self) -> usize {
        self.kind_of.len()
    }

    /// Number of nodes N + 1.
    pub fn nodes(&self) -> usize {
        self.node_x.len()
    }

    /// The distinct kinds of element.
    pub fn kinds(&self) -> &[ElementKind] {
        &self.kinds
    }

    /// The index in [`Self::kinds`] of element `e`.
    #[inline]
    pub fn kind(&self, e: usize) -> usize {
        self.kind_of[e]
    }

    /// Element `e` (length and section).
    #[inline]
    pub fn element(&self, e: usize) -> &BeamElement {
        &self.kinds[self.kind_of[e]].element
    }

    /// The strain-energy law of element `e`'s section.
    #[inline]
    pub fn strain_law(&self, e: usize) -> &StrainEnergy {
        &self.kinds[self.kind_of[e]].strain_law
    }

    /// x of node `i`, m.
    #[inline]
    pub fn node_x(&self, i: usize) -> f64 {
        self.node_x[i]
    }

    /// x of the midpoint of element `e`, m.
    #[inline]
    pub fn midpoint_x(&self, e: usize) -> f64 {
        self.midpoint_x[e]
    }

    /// x of every element's midpoint, m, top to bit.
    pub fn midpoints(&self) -> &[f64] {
        &self.midpoint_x
    }

    /// Per element, its index in [`Self::kinds`].
    pub fn kinds_of_elements(&self) -> &[usize] {
        &self.kind_of
    }

    /// The length of string node `i` stands for, m: half of each element it joins.
    pub fn tributary_length(&self, i: usize) -> f64 {
        let before = if i > 0 {
            self.element(i - 1).length
        } else {
            0.0
        };
        let after = if i < self.elements() {
            self.element(i).length
        } else {
            0.0
        };
        0.5 * (before + after)
    }

    /// The radial gap R_bh − R_ext at every node, m, R_ext the node's outer radius
    /// ([`Self::node_outer_radius`]).
    pub fn node_gaps(&self, borehole_radius: f64) -> Vec<f64> {
        (0..self.nodes())
            .map(|i| borehole_radius - self.node_outer_radius(i))
            .collect()
    }

    /// The factor on the wall law's force at every node, read `per` ([`WallStiffnessPer::factor`]
    /// of each node's tributary length).
    pub fn wall_factors(&self, per: WallStiffnessPer) -> Vec<f64> {
        (0..self.nodes())
            .map(|i| per.factor(self.tributary_length(i)))
            .collect()
    }

    /// The element holding position `x` (m, clamped to the string) and the fraction of its
    /// length at which x lies, in [0, 1].
    pub fn locate(&self, x: f64) -> (usize, f64) {
        let n = self.elements();
        if self.kinds.len() == 1 {
            // Equal elements: x/h directly.
            let h = self.kinds[0].element.length;
            let s = (x / h).clamp(0.0, n as f64);
            let i = (s.floor() as usize).min(n - 1);
            return (i, s - i as f64);
        }
        let x = x.clamp(0.0, self.node_x[n]);
        // The last node at or before x, at most the last element's first node.
        let e = self
            .node_x
            .partition_point(|&xi| xi <= x)
            .saturating_sub(1)
            .min(n - 1);
        let (a, b) = (self.node_x[e], self.node_x[e + 1]);
        (e, ((x - a) / (b - a)).clamp(0.0, 1.0))
    }
}

/// `elements` elements shared out over sections of `lengths` (m, or any weights): at least one
/// each, then one at a time to the section whose elements are the longest (ties to the first),
/// so that the element lengths are as even as the section lengths allow (for weights that are
/// element counts n_i and `elements` = k Σ n_i: exactly k n_i each).
///
/// # Panics
/// If `elements` is below the number of sections.
pub fn share_out(elements: usize, lengths: &[f64]) -> Vec<usize> {
    assert!(
        elements >= lengths.len(),
        "{elements} elements cannot cover {} sections",
        lengths.len()
    );
    let mut counts = vec![1; lengths.len()];
    for _ in lengths.len()..elements {
        let longest = (0..lengths.len())
            .max_by(|&a, &b| {
                let (ha, hb) = (lengths[a] / counts[a] as f64, lengths[b] / counts[b] as f64);
                ha.total_cmp(&hb).then(b.cmp(&a))
            })
            .expect("at least one section");
        counts[longest] += 1;
    }
    counts
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::test_support::seed_string as seed;

    #[test]
    fn elements_are_shared_out_by_length() {
        assert_eq!(share_out(10, &[90.0, 10.0]), vec![9, 1]);
        assert_eq!(share_out(3, &[1.0, 1.0, 1000.0]), vec![1, 1, 1]);
        assert_eq!(share_out(6, &[2.0, 1.0]), vec![4, 2]);
        assert_eq!(
            share_out(12, &[300.0, 100.0, 5.0]).iter().sum::<usize>(),
            12
        );
        // Counts as weights: their sum gives them back, twice the sum doubles each.
        assert_eq!(share_out(13, &[10.0, 2.0, 1.0]), vec![10, 2, 1]);
        assert_eq!(share_out(26, &[10.0, 2.0, 1.0]), vec![20, 4, 2]);
        assert_eq!(share_out(39, &[7.0, 5.0, 1.0]), vec![21, 15, 3]);
    }

    #[test]
    fn a_uniform_mesh_has_one_kind_and_nodes_at_multiples_of_h() {
        let s = seed();
        let l = ElementLayout::of(&s, 105);
        assert_eq!((l.elements(), l.nodes(), l.kinds().len()), (105, 106, 1));
        let h = s.length / 105.0;
        for i in 0..=105 {
            assert_eq!(l.node_x(i), i as f64 * h);
        }
        assert_eq!(l.element(17).length, h);
        assert_eq!(l.midpoint_x(3), 3.5 * h);
        let total: f64 = (0..=105).map(|i| l.tributary_length(i)).sum();
        approx::assert_relative_eq!(total, s.length, max_relative = 1e-13);
        assert_eq!(l.tributary_length(0), 0.5 * h);
        assert_eq!(l.tributary_length(50), h);
        let (e, f) = l.locate(10.5 * h);
        assert_eq!(e, 10);
        approx::assert_relative_eq!(f, 0.5, max_relative = 1e-9);
        assert_eq!(l.locate(s.length), (104, 1.0));
        assert_eq!(l.locate(-1.0), (0, 0.0));
    }
}
