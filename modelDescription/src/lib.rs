//! FMI 2.0 modelDescription.xml.
