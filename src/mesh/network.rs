//! A mesh as a two-point flux network: elements (volume and node) and the
//! connections between them, as simulators such as TOUGH read them.

/// An element: volume and node position (x, y, z; z up).
#[derive(Debug, Clone, PartialEq)]
pub struct Element {
    /// Its volume.
    pub volume: f64,
    /// Its node: the site, not the centroid (in 3D, the centroid where the
    /// site lies outside its cell: `Mesh3::network`).
    pub node: [f64; 3],
}

/// A connection between elements a and b.
#[derive(Debug, Clone, PartialEq)]
pub struct Connection {
    /// The two elements.
    pub elements: [usize; 2],
    /// Permeability index: 1, 2 or 3.
    pub isot: u8,
    /// Distances from each node to the interface (they differ in a power
    /// diagram).
    pub d: [f64; 2],
    /// The interface's area.
    pub area: f64,
    /// Cosine of the angle between gravity and the line from a to b
    /// (positive when b is below a).
    pub cos_gravity: f64,
}

impl Connection {
    /// A lateral connection between elements with nodes `na`, `nb` (z up):
    /// permeability index 1 or 2 by the larger horizontal component, the
    /// gravity cosine from the nodes.
    pub fn lateral(
        elements: [usize; 2],
        na: [f64; 3],
        nb: [f64; 3],
        d: [f64; 2],
        area: f64,
    ) -> Connection {
        let v = [nb[0] - na[0], nb[1] - na[1], nb[2] - na[2]];
        let len = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        Connection {
            elements,
            isot: if v[0].abs() >= v[1].abs() { 1 } else { 2 },
            d,
            area,
            cos_gravity: if len > 0.0 { -v[2] / len } else { 0.0 },
        }
    }
}

/// Elements and connections.
#[derive(Debug, Clone, Default)]
pub struct Network {
    /// One per cell.
    pub elements: Vec<Element>,
    /// One per interior face.
    pub connections: Vec<Connection>,
}
