"""Files: system files, parameter families and the shipped examples, read into the model
through its codec."""
