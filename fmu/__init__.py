"""The NC and its plant as an FMI 2.0/3.0 co-simulation FMU (self-contained, or lean with pythonfmu);
no NC logic here."""
