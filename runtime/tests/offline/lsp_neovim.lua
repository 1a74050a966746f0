-- The editor's part of runtime/tests/offline/lsp_neovim.rs: open a pipeline that uses
-- deferred.lbp, then deferred.lbp with its typo; wait for the diagnostics; hover and go to
-- definition at `params ambient.color`; go to definition on an entry point; complete a
-- half-typed `gbuf.alb` as the built-in omnifunc does; write what came back.
local out = {}
vim.cmd('edit ' .. vim.env.LB_DIR .. '/pipelines/deferred_gi.lbp')
vim.cmd('edit ' .. vim.env.LB_DIR .. '/pipelines/deferred.lbp')
local buf = vim.api.nvim_get_current_buf()
vim.wait(60000, function() return #vim.diagnostic.get(buf) > 0 end, 50)
-- Both pipelines' checks have had time to arrive.
vim.wait(2000)
out.diagnostics = {}
for _, d in ipairs(vim.diagnostic.get(buf)) do
  table.insert(out.diagnostics, { lnum = d.lnum, col = d.col, message = d.message, code = d.code })
end
local function find(needle, skip)
  for i, l in ipairs(vim.api.nvim_buf_get_lines(buf, 0, -1, false)) do
    local s = string.find(l, needle, 1, true)
    if s then return { line = i - 1, character = s - 1 + skip } end
  end
end
local function first(replies)
  for _, r in pairs(replies or {}) do return r.result end
  return vim.NIL
end
local function ask(method, position)
  local params = { textDocument = { uri = vim.uri_from_bufnr(buf) }, position = position }
  return first(vim.lsp.buf_request_sync(buf, method, params, 30000)) or vim.NIL
end
local hover = ask('textDocument/hover', find('params ambient.color', 8))
out.hover = hover ~= vim.NIL and hover and hover.contents.value or vim.NIL
out.definition = ask('textDocument/definition', find('params ambient.color', 8))
out.entry_definition = ask('textDocument/definition', find('fragment fs_fat_position', 12))

-- Completion: the line half-typed, the cursor after `gbuf.alb`; then what the omnifunc does
-- (Neovim 0.7's vim.lsp.omnifunc): the keyword before the cursor is the prefix, the items
-- are filtered by it, and the chosen word replaces the prefix.
local at = find('reads gbuf.albdo', 0)
local line = vim.api.nvim_buf_get_lines(buf, at.line, at.line + 1, false)[1]
local typed = line:sub(1, at.character) .. 'reads gbuf.alb'
vim.api.nvim_buf_set_lines(buf, at.line, at.line + 1, false, { typed .. ', gbuf.emissive' })
vim.api.nvim_win_set_cursor(0, { at.line + 1, #typed })
local start = vim.fn.match(typed, '\\k*$')
local prefix = typed:sub(start + 1)
local result = ask('textDocument/completion', { line = at.line, character = #typed })
local items = vim.lsp.util.text_document_completion_list_to_complete_items(result, prefix)
out.prefix = prefix
out.words = {}
for _, item in ipairs(items) do table.insert(out.words, item.word) end
out.completed = typed:sub(1, start) .. (out.words[1] or '') .. ', gbuf.emissive'
vim.fn.writefile({ vim.fn.json_encode(out) }, vim.env.LB_OUT)
vim.cmd('qa!')
