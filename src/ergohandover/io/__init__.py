"""Files in and out: atomic writes and the checked reading of user CSV files."""
