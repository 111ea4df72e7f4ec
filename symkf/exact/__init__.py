"""The exact substrate: exact input, algebraic numbers, number fields, exact linear algebra."""
