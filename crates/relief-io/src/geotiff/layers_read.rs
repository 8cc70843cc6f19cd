//! Reading a layer file (a GeoTIFF of one float band per layer, as
//! [`write_layers_geotiff`](crate::write_layers_geotiff) writes) back as a [`LayerRaster`].

use crate::format_error::FormatError;
use crate::geotiff::gdal_metadata::{band_descriptions, GDAL_METADATA_TAG};
use crate::geotiff::read::GeoTiffImage;
use crate::geotiff::tags::tag_error;
use crate::input_file::open_input;
use crate::{IoError, Layer, LayerRaster, ReadOptions};
use std::io::{BufReader, Read, Seek};
use std::path::Path;
use tiff::tags::Tag;

/// Reads every band of the GeoTIFF at `path` as the layers of a [`LayerRaster`]: row 0 south,
/// voids (GDAL_NODATA) as NaN, each layer named by its band's description (GDAL_METADATA),
/// `band N` (from 1) where there is none, with the file's georeference and nodata value.
///
/// Bands are read as [`read_geotiff`](crate::geotiff::read_geotiff) reads its one band (every sample
/// type, compression and chunk layout it reads); several bands must be stored in separate
/// planes (PlanarConfiguration 2), as relief and GDAL write them. The memory budget must hold
/// every band.
///
/// Errors: those of [`read_geotiff`](crate::geotiff::read_geotiff), and [`IoError::Unsupported`] for
/// several bands interleaved pixel by pixel.
pub fn read_layers_geotiff(path: &Path, options: &ReadOptions) -> Result<LayerRaster, IoError> {
    let (file, _) = open_input(path)?;
    read_layers_from(BufReader::new(file), options).map_err(|e| e.at(path))
}

/// [`read_layers_geotiff`] from a seekable reader, before the file is named.
fn read_layers_from<R: Read + Seek>(
    reader: R,
    options: &ReadOptions,
) -> Result<LayerRaster, FormatError> {
    let mut image = GeoTiffImage::open(reader, options, true)?;
    let names = match image.decoder.find_tag(Tag::Unknown(GDAL_METADATA_TAG)) {
        Ok(Some(value)) => {
            let xml = value.into_string().map_err(tag_error("GDAL_METADATA"))?;
            band_descriptions(&xml, image.bands)
        }
        Ok(None) => vec![None; image.bands],
        Err(e) => return Err(tag_error("GDAL_METADATA")(e)),
    };
    let mut layers = Vec::with_capacity(image.bands);
    for (band, name) in names.into_iter().enumerate() {
        let samples = image.decode_band(band)?;
        layers.push(Layer { name: name.unwrap_or_else(|| format!("band {}", band + 1)), samples });
    }
    Ok(LayerRaster {
        width: image.width,
        height: image.height,
        layers,
        georeference: image.info.georeference,
        nodata: image.info.nodata,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_dir::TestDir;
    use crate::{write_layers_geotiff, Georeference};

    #[test]
    fn a_layer_file_reads_back_as_written() {
        let dir = TestDir::new("layers-read");
        let (width, height) = (37, 29);
        let layer = |name: &str, k: f32| Layer {
            name: name.into(),
            samples: (0..width * height)
                .map(|i| if i % 31 == 4 { f32::NAN } else { (i as f32 * k).sin() })
                .collect(),
        };
        for (nodata, georeference) in
            [(Some(-2.0), Some(Georeference::srtm_tile(36, -85, 1201))), (None, None)]
        {
            let written = LayerRaster {
                width,
                height,
                layers: vec![layer("shadow", 0.1), layer("a&b <c>", 0.2), layer("é", 0.3)],
                georeference,
                nodata,
            };
            let path = dir.path().join("layers.tif");
            write_layers_geotiff(&path, &written).unwrap();
            let back = read_layers_geotiff(&path, &ReadOptions::default()).unwrap();
            assert_eq!((back.width, back.height), (width, height));
            assert_eq!(back.georeference, written.georeference);
            // Without a nodata value, the voids are declared as NaN.
            match nodata {
                Some(v) => assert_eq!(back.nodata, Some(v)),
                None => assert!(back.nodata.is_some_and(f64::is_nan), "{:?}", back.nodata),
            }
            assert_eq!(back.layers.len(), 3);
            for (a, b) in back.layers.iter().zip(&written.layers) {
                assert_eq!(a.name, b.name);
                assert!(a
                    .samples
                    .iter()
                    .zip(&b.samples)
                    .all(|(x, y)| x.to_bits() == y.to_bits() || (x.is_nan() && y.is_nan())));
            }
            // The single-band reader refuses several bands, as before.
            let err = crate::geotiff::read_geotiff(&path, &ReadOptions::default()).unwrap_err();
            assert!(err.to_string().contains("3 bands"), "{err}");
        }
    }
}
