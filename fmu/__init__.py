"""FMI 2.0 co-simulation facade over the NC core (built with pythonfmu); no NC logic here."""
