//! Interface building: each interface of the problem ([`InterfaceDef`]) turned
//! into an [`Interface`] with its coupling elements — the pair search, the coupling
//! nodes moved onto their host edges, the segment coupling's elements — and the
//! overrides of a prepared interface's law and friction.

use super::search3d::{self, Surface};
use super::volume::{self, VolumeDim};
use super::{
    Coupling, CouplingElement, CouplingForm, Interface, Law, SLIP_STIFFNESS, search, segment,
};
use crate::dim::{D2, D3};
use crate::domain::{InterfaceDef, Part};
use crate::error::{Error, Result};
use crate::fem::ElementFamily;

/// How the interfaces of a dimension are built: the pair search, the nodes
/// moved onto the host's boundary, and the slip stiffness — node to edge (or
/// segment) in 2D, node to face in 3D.
pub trait InterfaceDim: ElementFamily {
    /// The interfaces of `defs` over `parts` ([`interfaces`]).
    fn build(defs: &[InterfaceDef], parts: &mut [Part<Self>], refine: usize) -> Result<Vec<Interface<Self>>>;

    /// The stabilising tangential stiffness of a slipping pair of `elements`
    /// between `host` and `node` under `law` (0 but for the Coulomb law).
    fn slip_stiffness(law: Law, host: &Part<Self>, node: &Part<Self>, elements: &[CouplingElement<Self>]) -> f64;
}

/// Node to edge (or segment) coupling of plane parts.
impl InterfaceDim for D2 {
    fn build(defs: &[InterfaceDef], parts: &mut [Part], refine: usize) -> Result<Vec<Interface>> {
        plane_interfaces(defs, parts, refine)
    }

    /// [`SLIP_STIFFNESS`] × the softer side's E·t.
    fn slip_stiffness(law: Law, host: &Part, node: &Part, _: &[CouplingElement]) -> f64 {
        let et = |p: &Part| p.material.young * p.material.thickness;
        if law == Law::Coulomb {
            SLIP_STIFFNESS * et(host).min(et(node))
        } else {
            0.0
        }
    }
}

/// Node to face coupling of solid parts.
impl InterfaceDim for D3 {
    fn build(defs: &[InterfaceDef], parts: &mut [Part<D3>], refine: usize) -> Result<Vec<Interface<D3>>> {
        solid_interfaces(defs, parts, refine)
    }

    /// [`SLIP_STIFFNESS`] × the softer side's E × the mean size of the
    /// interface's host faces (a force per length, as E·t is in 2D).
    fn slip_stiffness(law: Law, host: &Part<D3>, node: &Part<D3>, elements: &[CouplingElement<D3>]) -> f64 {
        if law != Law::Coulomb || elements.is_empty() {
            return 0.0;
        }
        let h = elements.iter().map(|c| c.edge_length).sum::<f64>() / elements.len() as f64;
        SLIP_STIFFNESS * host.material.young.min(node.material.young) * h
    }
}

/// The interfaces of `defs` over `parts` (meshed `refine` times finer than the
/// problem file gives them), in order, each seeing the nodes the earlier ones
/// moved ([`InterfaceDim::build`] of the parts' dimension).
pub fn interfaces<D: InterfaceDim>(
    defs: &[InterfaceDef],
    parts: &mut [Part<D>],
    refine: usize,
) -> Result<Vec<Interface<D>>> {
    D::build(defs, parts, refine)
}

/// The interfaces of plane `defs` over `parts`: finds the coupling pairs of every
/// interface and moves each coupling node onto its host edge (its projection
/// there: a no-op for faces that already coincide, a small adjustment for a
/// curved face meshed apart).
fn plane_interfaces(
    defs: &[InterfaceDef],
    parts: &mut [Part],
    refine: usize,
) -> Result<Vec<Interface>> {
    let mut interfaces = Vec::with_capacity(defs.len());
    for def in defs {
        if def.form == CouplingForm::Volume {
            let mut iface = volume_interface(def, parts)?;
            if parts[def.node_part].material.is_axisymmetric() {
                // Each pair stands for the ring of its node's radius.
                for c in &mut iface.elements {
                    c.ring = 2.0 * std::f64::consts::PI * c.position[0];
                }
            }
            interfaces.push(iface);
            continue;
        }
        let host = &parts[def.host];
        let node_part = &parts[def.node_part];
        // The tolerance is a fraction of the host's edges as meshed in the
        // problem file: `--refine K` subdivides edges K times but leaves the gap
        // between two faces meshed apart (a Gmsh part keeps its polygons) as it is.
        // The segment coupling within a search distance moves no node and
        // finds its own host edges, point by point along the face.
        let segment_gaps = def.coupling == Coupling::Segment && def.search_distance > 0.0;
        let (mut elements, mut unpaired) = if segment_gaps {
            (Vec::new(), 0)
        } else {
            search::find_pairs_within(
                &def.name,
                &host.mesh,
                &node_part.mesh,
                &def.nodes,
                def.tolerance * refine as f64,
                def.search_distance,
            )?
        };
        // Within a search distance the nodes stay where they are (their gaps
        // are kept): nothing is moved.
        let max_projection_distance = if def.search_distance > 0.0 {
            0.0
        } else {
            elements.iter().map(|c| c.distance).fold(0.0, f64::max)
        };
        if max_projection_distance > 0.0 {
            let part = &mut parts[def.node_part];
            for c in &elements {
                part.mesh.nodes[c.node] = c.position;
            }
            let moved: Vec<usize> = elements.iter().map(|c| c.node).collect();
            part.mesh
                .validate_around(&part.name, &moved)
                .map_err(|e| Error::Coupling {
                interface: def.name.clone(),
                message: format!(
                    "moving the coupling nodes onto the host edges (by up to {max_projection_distance:e}) spoils the node part's mesh: {e}; lower `tolerance` or mesh the faces closer together"
                ),
            })?;
        }
        if def.coupling == Coupling::Segment {
            // The nodes now lie on the host boundary (or, within a search
            // distance, stay where they are): integrate over their face
            // segments.
            let (segment_elements, segment_unpaired) = segment::segment_elements_within(
                &def.name,
                &parts[def.host].mesh,
                &parts[def.node_part].mesh,
                &def.boundary,
                &def.nodes,
                def.tolerance * refine as f64,
                def.search_distance,
                if parts[def.node_part].material.is_axisymmetric() {
                    segment::FaceMeasure::Ring
                } else {
                    segment::FaceMeasure::Length
                },
            )?;
            elements = segment_elements;
            if segment_gaps {
                unpaired = segment_unpaired;
            }
        }
        if elements.is_empty() && !def.nodes.is_empty() && def.search_distance > 0.0 {
            return Err(no_pairs(
                def,
                &parts[def.host],
                &parts[def.node_part],
            ));
        }
        if parts[def.node_part].material.is_axisymmetric() {
            // Each pair stands for its ring: penalties and forces per unit
            // circumference times 2π r̄.
            let rings = crate::fem::axisymmetric::face_rings(&parts[def.node_part].mesh, &def.nodes);
            // (A segment element has its own, integrated over its share.)
            for c in elements.iter_mut().filter(|c| c.segment.is_none()) {
                c.ring = rings
                    .get(&c.node)
                    .copied()
                    .unwrap_or(2.0 * std::f64::consts::PI * c.position[0]);
            }
        }
        interfaces.push(prepared(def, parts, elements, max_projection_distance, unpaired));
    }
    Ok(interfaces)
}

/// The interfaces of solid `defs` over `parts`: node to face pairs
/// ([`search3d::find_pairs_3d`] on the host's boundary faces), each coupling node
/// moved onto its host face unless a search distance keeps the gaps.
fn solid_interfaces(
    defs: &[InterfaceDef],
    parts: &mut [Part<D3>],
    refine: usize,
) -> Result<Vec<Interface<D3>>> {
    let mut interfaces = Vec::with_capacity(defs.len());
    for def in defs {
        if def.form == CouplingForm::Volume {
            interfaces.push(volume_interface(def, parts)?);
            continue;
        }
        if def.coupling == Coupling::Segment {
            return Err(Error::Coupling {
                interface: def.name.clone(),
                message: "coupling = \"segment\" is for plane parts only (in 3D it needs the polygon clipping of two face meshes): solid parts couple node to face, leave `coupling` out".into(),
            });
        }
        let (host, node_part) = (&parts[def.host], &parts[def.node_part]);
        let host_faces = host.mesh.boundary_faces();
        let node_faces = match node_part.mesh.boundaries.get(&def.boundary) {
            Some(faces) => faces.clone(),
            None => node_part.mesh.boundary_faces(),
        };
        let (elements, unpaired) = search3d::find_pairs_3d(
            &def.name,
            Surface {
                nodes: &host.mesh.nodes,
                faces: &host_faces,
            },
            Surface {
                nodes: &node_part.mesh.nodes,
                faces: &node_faces,
            },
            &def.nodes,
            def.tolerance * refine as f64,
            def.search_distance,
        )?;
        if elements.is_empty() && !def.nodes.is_empty() && def.search_distance > 0.0 {
            // Measured on this failure only: the nearest node–face distance.
            let nearest = search3d::nearest_face_distance(
                Surface {
                    nodes: &host.mesh.nodes,
                    faces: &host_faces,
                },
                Surface {
                    nodes: &node_part.mesh.nodes,
                    faces: &node_faces,
                },
                &def.nodes,
            );
            return Err(Error::NoPairs {
                interface: def.name.clone(),
                search_distance: def.search_distance,
                nearest,
                message: format!(
                    "no pair within search_distance = {}: none of the {} coupling nodes of part '{}' (boundary '{}') lies within it of a boundary face of part '{}' facing it{}; the pairs are fixed in the initial configuration, so the interface would couple nothing: raise `search_distance` or place the faces closer",
                    def.search_distance,
                    def.nodes.len(),
                    node_part.name,
                    def.boundary,
                    host.name,
                    nearest.map_or(String::new(), |d| format!(" (the nearest is {d:e} away)")),
                ),
            });
        }
        let max_projection_distance = if def.search_distance > 0.0 {
            0.0
        } else {
            search3d::move_onto_faces(&mut parts[def.node_part].mesh.nodes, &elements)
        };
        if max_projection_distance > 0.0 {
            let part = &parts[def.node_part];
            part.mesh.validate(&part.name).map_err(|e| Error::Coupling {
                interface: def.name.clone(),
                message: format!(
                    "moving the coupling nodes onto the host faces (by up to {max_projection_distance:e}) spoils the node part's mesh: {e}; lower `tolerance` or mesh the faces closer together"
                ),
            })?;
        }
        interfaces.push(prepared(def, parts, elements, max_projection_distance, unpaired));
    }
    Ok(interfaces)
}

/// The prepared interface of `def` with its coupling `elements`: the
/// definition's law, penalties and contact settings, the slip stiffness of its
/// law and parts, how far its nodes were moved onto the host and how many of
/// them found no host (`unpaired`). One constructor for every dimension and
/// form.
fn prepared<D: InterfaceDim>(
    def: &InterfaceDef,
    parts: &[Part<D>],
    elements: Vec<CouplingElement<D>>,
    max_projection_distance: f64,
    unpaired: usize,
) -> Interface<D> {
    Interface {
        name: def.name.clone(),
        host: def.host,
        node_part: def.node_part,
        law: def.law,
        c_n: def.c_n,
        c_s: def.c_s,
        c_slip: D::slip_stiffness(def.law, &parts[def.host], &parts[def.node_part], &elements),
        elements,
        max_projection_distance,
        friction: def.friction,
        enforcement: def.enforcement,
        penetration_tolerance: def.penetration_tolerance,
        unpaired,
        coupling: def.coupling,
        form: def.form,
    }
}

/// The interface of `def` in volume form ([`volume`]): each of its coupling
/// nodes inside an element of the host tied to it, the nodes outside counted
/// (`unpaired`); nothing moves.
///
/// Errors ([`Error::Coupling`]): a law other than `rigid`, c_n ≠ c_s (a node
/// inside a body has no face, so no normal: only the bonded tie c·I is the
/// same in every frame), a search distance or the segment coupling (both read
/// a face), and an interface none of whose nodes lies inside the host.
fn volume_interface<D: InterfaceDim + VolumeDim>(
    def: &InterfaceDef,
    parts: &[Part<D>],
) -> Result<Interface<D>> {
    let refuse = |message: String| Error::Coupling {
        interface: def.name.clone(),
        message,
    };
    if def.law != Law::Rigid {
        return Err(refuse(format!(
            "form = \"volume\" ties nodes inside the host's elements, where there is no face and so no normal, and law = \"{}\" needs one (its gap, pressure and slip are measured along the host face's normal): use law = \"rigid\" (a bonded tie), or couple the node part's boundary on the host's boundary in face form (leave `form` out)",
            def.law.as_str()
        )));
    }
    if def.c_n != def.c_s {
        return Err(refuse(format!(
            "form = \"volume\" has no face, so no normal to tell c_n = {:e} from c_s = {:e}: the tie must be the same in every direction (c·I); give c_s = c_n (or leave c_s out)",
            def.c_n, def.c_s
        )));
    }
    if def.search_distance > 0.0 || def.coupling == Coupling::Segment {
        return Err(refuse(
            "form = \"volume\" couples nodes inside the host's elements: `search_distance` and coupling = \"segment\" measure gaps to the host's faces and do not apply; leave them out".into(),
        ));
    }
    let (host, node_part) = (&parts[def.host], &parts[def.node_part]);
    let (elements, outside) = volume::embedded_elements(&host.mesh, &node_part.mesh.nodes, &def.nodes);
    if elements.is_empty() && !def.nodes.is_empty() {
        return Err(refuse(format!(
            "form = \"volume\": none of the {} coupling nodes of part '{}'{} lies inside an element of part '{}', so the interface would couple nothing: check that the parts overlap",
            def.nodes.len(),
            node_part.name,
            if def.boundary.is_empty() {
                String::new()
            } else {
                format!(" (boundary '{}')", def.boundary)
            },
            host.name
        )));
    }
    Ok(prepared(def, parts, elements, 0.0, outside))
}

/// Makes every interface in face form (its definition and its prepared form)
/// follow `law` (an interface without tangential stiffness, c_s = 0, as the
/// frictionless law allows, gets c_s = c_n under any other law); one in volume form stays the rigid tie it must be (it has no
/// normal: [`volume`]).
pub fn set_law<D: InterfaceDim>(
    defs: &mut [InterfaceDef],
    interfaces: &mut [Interface<D>],
    parts: &[Part<D>],
    law: Law,
) {
    // c_s = 0 is allowed (and the default) only with the frictionless law: a
    // law that needs a tangential stiffness gets the default any other law
    // has, c_s = c_n — or a Coulomb interface would have no friction at all.
    let c_s = |law: Law, c_n: f64, c_s: f64| {
        if law != Law::Frictionless && c_s == 0.0 {
            c_n
        } else {
            c_s
        }
    };
    for def in defs.iter_mut().filter(|d| d.form == CouplingForm::Face) {
        def.law = law;
        def.c_s = c_s(law, def.c_n, def.c_s);
    }
    for iface in interfaces.iter_mut().filter(|i| i.form == CouplingForm::Face) {
        iface.law = law;
        iface.c_s = c_s(law, iface.c_n, iface.c_s);
        iface.c_slip = D::slip_stiffness(law, &parts[iface.host], &parts[iface.node_part], &iface.elements);
    }
}

/// Makes every interface in face form follow the Coulomb law with friction
/// coefficient `mu`, which must be finite and ≥ 0 ([`Error::Model`]
/// otherwise); one in volume form stays a rigid tie.
pub fn set_friction<D: InterfaceDim>(
    defs: &mut [InterfaceDef],
    interfaces: &mut [Interface<D>],
    parts: &[Part<D>],
    mu: f64,
) -> Result<()> {
    if !(mu.is_finite() && mu >= 0.0) {
        return Err(Error::Model(format!(
            "the friction coefficient must be finite and ≥ 0, not {mu}"
        )));
    }
    set_law(defs, interfaces, parts, Law::Coulomb);
    for def in defs.iter_mut().filter(|d| d.form == CouplingForm::Face) {
        def.friction = mu;
    }
    for iface in interfaces.iter_mut().filter(|i| i.form == CouplingForm::Face) {
        iface.friction = mu;
    }
    Ok(())
}

/// The error of interface `def`, whose search distance found no pair, with the
/// distance from its nearest coupling node to the nearest host boundary edge
/// (measured over every node and boundary edge: only on this failure, and both
/// are boundaries, so about as many products as the model has nodes).
fn no_pairs(def: &InterfaceDef, host: &Part, node_part: &Part) -> Error {
    let edges = host.mesh.boundary_edges();
    let nearest = def
        .nodes
        .iter()
        .flat_map(|&n| {
            let p = node_part.mesh.nodes[n];
            edges.iter().map(move |e| {
                let [a, b] = e.nodes.map(|k| host.mesh.nodes[k]);
                search::project(p, a, b).1
            })
        })
        .fold(f64::INFINITY, f64::min);
    let nearest = nearest.is_finite().then_some(nearest);
    Error::NoPairs {
        interface: def.name.clone(),
        search_distance: def.search_distance,
        nearest,
        message: format!(
            "no pair within search_distance = {}: none of the {} coupling nodes of part '{}' (boundary '{}') lies within it of a boundary edge of part '{}'{}; the pairs are fixed in the initial configuration, so the interface would couple nothing: raise `search_distance` or place the faces closer",
            def.search_distance,
            def.nodes.len(),
            node_part.name,
            def.boundary,
            host.name,
            nearest.map_or(String::new(), |d| format!(" (the nearest is {d:e} away)")),
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::domain::Enforcement;
    use crate::fem::{Material, PlaneKind};
    use crate::mesh::{ElementKind, Mesh};

    /// A T3 base (E·t = 2e5) under a softer Q4 block (E·t = 2e3) meshed apart along
    /// y = 1, and the contact interface of the block's bottom on the base.
    fn base_and_block() -> (Vec<Part>, Vec<InterfaceDef>) {
        let part = |name: &str, mesh, young, thickness| Part {
            name: name.into(),
            mesh,
            material: Material::new(young, 0.3, PlaneKind::Stress, thickness, name).unwrap(),
        };
        let parts = vec![
            part(
                "base",
                Mesh::rectangle([0.0, 2.0], [0.0, 1.0], [2, 1], ElementKind::T3),
                2e5,
                1.0,
            ),
            part(
                "block",
                Mesh::rectangle([0.0, 2.0], [1.0, 2.0], [4, 2], ElementKind::Q4),
                1e3,
                2.0,
            ),
        ];
        let def = InterfaceDef {
            name: "base/block".into(),
            host: 0,
            node_part: 1,
            nodes: parts[1].mesh.boundary_nodes("bottom").unwrap(),
            boundary: "bottom".into(),
            law: Law::Contact,
            c_n: 1e6,
            c_s: 1e6,
            tolerance: 1e-3,
            friction: 0.0,
            search_distance: 0.0,
            enforcement: Enforcement::Penalty,
            penetration_tolerance: 0.0,
            coupling: Coupling::Node,
            form: CouplingForm::Face,
        };
        (parts, vec![def])
    }

    /// Faces that coincide: every coupling node pairs with a base element, at its
    /// own position (nothing moves), and the interface carries its definition's
    /// law and penalties, with no slip stiffness outside the Coulomb law.
    #[test]
    fn coinciding_faces_pair_every_node_in_place() {
        let (mut parts, defs) = base_and_block();
        let before = parts[1].mesh.nodes.clone();
        let ifaces = interfaces(&defs, &mut parts, 1).unwrap();
        assert_eq!(ifaces.len(), 1);
        let iface = &ifaces[0];
        assert_eq!(iface.elements.len(), 5);
        assert_eq!(parts[1].mesh.nodes, before);
        assert_eq!(iface.max_projection_distance, 0.0);
        for c in &iface.elements {
            assert_eq!(c.position, before[c.node]);
            assert!(c.host_element < parts[0].mesh.elements.len());
        }
        assert_eq!((iface.law, iface.c_n, iface.c_s), (Law::Contact, 1e6, 1e6));
        assert_eq!(iface.c_slip, 0.0);
    }

    /// A frictionless interface without tangential stiffness (c_s = 0, its
    /// default) made Coulomb or contact by the law override gets c_s = c_n
    /// (any other law's default), so friction is not silently absent; made
    /// frictionless again, it keeps that c_s (the law ignores it).
    #[test]
    fn a_law_override_gives_a_frictionless_interface_its_tangential_stiffness() {
        let (mut parts, mut defs) = base_and_block();
        defs[0].law = Law::Frictionless;
        defs[0].c_s = 0.0;
        let mut ifaces = interfaces(&defs, &mut parts, 1).unwrap();
        assert_eq!(ifaces[0].c_s, 0.0);
        set_friction(&mut defs, &mut ifaces, &parts, 0.3).unwrap();
        assert_eq!((defs[0].c_s, ifaces[0].c_s), (1e6, 1e6));
        set_law(&mut defs, &mut ifaces, &parts, Law::Frictionless);
        assert_eq!((defs[0].law, ifaces[0].c_s), (Law::Frictionless, 1e6));
    }

    /// The friction override refuses a negative or NaN μ and changes nothing then;
    /// a valid μ makes every interface Coulomb with that μ and a slip stiffness of
    /// SLIP_STIFFNESS × the softer part's E·t (the block's 1e3 × 2).
    #[test]
    fn friction_override_checks_mu_and_sets_the_slip_stiffness() {
        let (mut parts, mut defs) = base_and_block();
        let mut ifaces = interfaces(&defs, &mut parts, 1).unwrap();
        for mu in [-0.1, f64::NAN, f64::INFINITY] {
            let e = set_friction(&mut defs, &mut ifaces, &parts, mu);
            assert!(matches!(e, Err(Error::Model(_))), "{mu}: {e:?}");
            assert_eq!((defs[0].law, ifaces[0].law), (Law::Contact, Law::Contact));
        }
        set_friction(&mut defs, &mut ifaces, &parts, 0.3).unwrap();
        assert_eq!((defs[0].law, defs[0].friction), (Law::Coulomb, 0.3));
        assert_eq!((ifaces[0].law, ifaces[0].friction), (Law::Coulomb, 0.3));
        assert_eq!(ifaces[0].c_slip, SLIP_STIFFNESS * 2e3);
        set_law(&mut defs, &mut ifaces, &parts, Law::Rigid);
        assert_eq!((defs[0].law, ifaces[0].law, ifaces[0].c_slip), (Law::Rigid, Law::Rigid, 0.0));
    }
}
