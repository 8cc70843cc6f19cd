//! GDAL's metadata tag (GDAL_METADATA, TIFF tag 42112): the XML that names each band, so that
//! GDAL (and rasterio's `descriptions`) give a layer file's bands their layers' names.

/// TIFF tag of GDAL's metadata XML.
pub(crate) const GDAL_METADATA_TAG: u16 = 42112;

/// The GDAL_METADATA XML describing band `i` (from 0) as `names[i]`:
/// `<GDALMetadata>` with one `<Item name="DESCRIPTION" sample="i" role="description">` each.
/// `&`, `<`, `>` and `"` are escaped twice, as GDAL writes them (it escapes a value, then its
/// XML writer escapes the text again; reading, it unescapes twice): `a&b` is `a&amp;amp;b`.
pub(crate) fn band_descriptions_xml<S: AsRef<str>>(names: &[S]) -> String {
    let mut xml = String::from("<GDALMetadata>\n");
    for (sample, name) in names.iter().enumerate() {
        xml.push_str(&format!(
            "  <Item name=\"DESCRIPTION\" sample=\"{sample}\" role=\"description\">{}</Item>\n",
            escape(&escape(name.as_ref()))
        ));
    }
    xml.push_str("</GDALMetadata>");
    xml
}

/// The band descriptions of a GDAL_METADATA XML, for `bands` bands: `None` where it names
/// none. Items of other kinds are skipped; text that is not GDAL's XML names nothing.
pub(crate) fn band_descriptions(xml: &str, bands: usize) -> Vec<Option<String>> {
    let mut names = vec![None; bands];
    for item in xml.split("<Item ").skip(1) {
        let Some((attributes, rest)) = item.split_once('>') else { continue };
        let Some((text, _)) = rest.split_once("</Item>") else { continue };
        let attribute = |key: &str| {
            let start = attributes.find(&format!("{key}=\""))? + key.len() + 2;
            let len = attributes[start..].find('"')?;
            Some(&attributes[start..start + len])
        };
        if attribute("role") != Some("description") {
            continue;
        }
        let sample = attribute("sample").and_then(|s| s.parse::<usize>().ok());
        if let Some(slot) = sample.and_then(|s| names.get_mut(s)) {
            *slot = Some(unescape(&unescape(text)));
        }
    }
    names
}

/// `text` with XML's special characters as entities.
fn escape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            c => out.push(c),
        }
    }
    out
}

/// `text` with the entities [`escape`] writes (and `&apos;`) replaced by their characters.
fn unescape(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find('&') {
        out.push_str(&rest[..at]);
        rest = &rest[at..];
        let entity =
            [("&amp;", '&'), ("&lt;", '<'), ("&gt;", '>'), ("&quot;", '"'), ("&apos;", '\'')]
                .into_iter()
                .find(|(e, _)| rest.starts_with(e));
        match entity {
            Some((e, c)) => {
                out.push(c);
                rest = &rest[e.len()..];
            }
            None => {
                out.push('&');
                rest = &rest[1..];
            }
        }
    }
    out.push_str(rest);
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_each_band_and_escapes_markup() {
        let xml = band_descriptions_xml(&["shadow", "a&b <c> \"d\""]);
        assert_eq!(
            xml,
            "<GDALMetadata>\n  \
             <Item name=\"DESCRIPTION\" sample=\"0\" role=\"description\">shadow</Item>\n  \
             <Item name=\"DESCRIPTION\" sample=\"1\" role=\"description\">\
             a&amp;amp;b &amp;lt;c&amp;gt; &amp;quot;d&amp;quot;</Item>\n</GDALMetadata>"
        );
        assert_eq!(
            band_descriptions(&xml, 3),
            [Some("shadow".into()), Some("a&b <c> \"d\"".into()), None]
        );
    }

    #[test]
    fn other_items_and_broken_text_name_nothing() {
        let xml = "<GDALMetadata><Item name=\"SCALE\" sample=\"0\" role=\"scale\">2</Item>\
                   <Item name=\"DESCRIPTION\" sample=\"9\" role=\"description\">x</Item>\
                   <Item name=\"DESCRIPTION\" sample=\"0\" role=\"description\">ok &bogus;";
        assert_eq!(band_descriptions(xml, 1), [None]);
        assert_eq!(band_descriptions("not xml", 2), [None, None]);
        assert_eq!(unescape("&amp;&bogus;&"), "&&bogus;&");
    }
}
