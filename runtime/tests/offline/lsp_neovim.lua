-- The editor's part of runtime/tests/offline/lsp_neovim.rs: open the pipeline, wait for the
-- diagnostics, hover and go to definition at `params ambient.color`, write what came back.
local out = {}
vim.cmd('edit ' .. vim.env.LB_DIR .. '/pipelines/deferred.lbp')
local buf = vim.api.nvim_get_current_buf()
vim.wait(60000, function() return #vim.diagnostic.get(buf) > 0 end, 50)
out.diagnostics = {}
for _, d in ipairs(vim.diagnostic.get(buf)) do
  table.insert(out.diagnostics, { lnum = d.lnum, col = d.col, message = d.message, code = d.code })
end
local line
for i, l in ipairs(vim.api.nvim_buf_get_lines(buf, 0, -1, false)) do
  local s = string.find(l, 'params ambient.color', 1, true)
  if s and not line then line = { line = i - 1, character = s - 1 + 8 } end
end
local params = { textDocument = { uri = vim.uri_from_bufnr(buf) }, position = line }
local function first(replies)
  for _, r in pairs(replies or {}) do return r.result end
  return vim.NIL
end
local hover = first(vim.lsp.buf_request_sync(buf, 'textDocument/hover', params, 30000))
out.hover = hover ~= vim.NIL and hover and hover.contents.value or vim.NIL
out.definition = first(vim.lsp.buf_request_sync(buf, 'textDocument/definition', params, 30000)) or vim.NIL
vim.fn.writefile({ vim.fn.json_encode(out) }, vim.env.LB_OUT)
vim.cmd('qa!')
