"""What is stored: the schema's names, datasets, typed views of them, the model file, caches and output folders."""
