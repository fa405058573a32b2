-- Vendor parameters the machine model does not read, kept verbatim (a control keeps every
-- parameter it is given): a JSON object in the controller's dialect numbering.
ALTER TABLE controllers ADD COLUMN extra_parameters TEXT NOT NULL DEFAULT '{}';
