"""What people read: LaTeX tables and figures."""
