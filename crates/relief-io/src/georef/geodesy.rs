//! Degrees to metres on the WGS84 ellipsoid, for rasters georeferenced in longitude/latitude.

/// WGS84 semi-major axis in metres.
const WGS84_A: f64 = 6_378_137.0;
/// WGS84 first eccentricity squared.
const WGS84_E2: f64 = 6.694_379_990_14e-3;

/// Metres per degree of longitude and of latitude at `latitude_deg` on the WGS84 ellipsoid
/// (prime-vertical and meridional radii of curvature).
///
/// At 36.6° N a 3 arc-second pixel is about 74.5 m east-west and 92.5 m north-south.
pub fn metres_per_degree(latitude_deg: f64) -> (f64, f64) {
    let phi = latitude_deg.to_radians();
    let w2 = 1.0 - WGS84_E2 * phi.sin().powi(2);
    let prime_vertical = WGS84_A / w2.sqrt();
    let meridional = WGS84_A * (1.0 - WGS84_E2) / (w2 * w2.sqrt());
    let per_radian_to_degree = std::f64::consts::PI / 180.0;
    (prime_vertical * phi.cos() * per_radian_to_degree, meridional * per_radian_to_degree)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn three_arc_seconds_at_jacksboro() {
        let (per_lon, per_lat) = metres_per_degree(36.6);
        let arc3 = 3.0 / 3600.0;
        assert!((per_lon * arc3 - 74.5).abs() < 0.2, "{}", per_lon * arc3);
        assert!((per_lat * arc3 - 92.5).abs() < 0.2, "{}", per_lat * arc3);
        let (eq_lon, eq_lat) = metres_per_degree(0.0);
        assert!((eq_lon - 111_319.5).abs() < 1.0 && (eq_lat - 110_574.3).abs() < 1.0);
    }
}
