// eval: compare metrics and bench (later issue)
