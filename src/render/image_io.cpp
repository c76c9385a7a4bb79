// Placeholder until image output lands.
