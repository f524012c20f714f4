"""The jobs: each ties the computations together and returns a result; none parses arguments or draws a report."""
