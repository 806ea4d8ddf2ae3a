//! Mitsuba XML reader (stub; implemented by the XML work).
