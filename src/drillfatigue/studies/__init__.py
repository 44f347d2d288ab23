"""The founding paper's case studies and the well-plan ranking tool (MODEL.md §8)."""
