-- The editor's part of `cargo bench -p lightbench --bench lsp`, end to end: headless Neovim
-- with the manual's snippet opens deferred_gi.lbp, deferred.lbp (which the first uses) and
-- the shader ambient.wgsl (which both use), then types: a two-letter typo into deferred.lbp
-- and out again (keystrokes 40 ms apart), a one-letter error into the shader and out again,
-- and times each last keystroke to the publication that shows its result (as the client's
-- handler gets it).
local dir, rounds = vim.env.LB_DIR, tonumber(vim.env.LB_ROUNDS)
local published = {}
local shown = vim.lsp.handlers['textDocument/publishDiagnostics']
vim.lsp.handlers['textDocument/publishDiagnostics'] = function(err, result, ctx, config)
  local list = published[result.uri] or {}
  local first = result.diagnostics[1]
  table.insert(list, { t = vim.loop.hrtime(), n = #result.diagnostics, m = first and first.message or '' })
  published[result.uri] = list
  return shown(err, result, ctx, config)
end

local function open(file)
  vim.cmd('edit ' .. dir .. '/' .. file)
  return vim.api.nvim_get_current_buf()
end
-- The first publication for `buf` after `since` that `want` accepts (given the count of
-- diagnostics and the first one's message): milliseconds.
local function published_after(buf, since, want)
  local uri, took = vim.uri_from_bufnr(buf), nil
  vim.wait(30000, function()
    for _, p in ipairs(published[uri] or {}) do
      if p.t > since and want(p.n, p.m) then
        took = (p.t - since) / 1e6
        return true
      end
    end
    return false
  end, 1)
  return took or -1
end
local function line_of(buf, needle)
  for i, l in ipairs(vim.api.nvim_buf_get_lines(buf, 0, -1, false)) do
    if string.find(l, needle, 1, true) then return i - 1, l end
  end
end
-- Keystrokes 40 ms apart on line `row` after byte `col`: each character of `keys` typed, or
-- (`keys` a number) that many backspaces; the time of the last keystroke.
local function type_at(buf, row, col, keys)
  local last
  local count = type(keys) == 'number' and keys or #keys
  for i = 1, count do
    local l = vim.api.nvim_buf_get_lines(buf, row, row + 1, false)[1]
    if type(keys) == 'number' then
      local at = col + count - i + 1
      l = l:sub(1, at - 1) .. l:sub(at + 1)
    else
      l = l:sub(1, col + i - 1) .. keys:sub(i, i) .. l:sub(col + i)
    end
    vim.api.nvim_buf_set_lines(buf, row, row + 1, false, { l })
    last = vim.loop.hrtime()
    vim.wait(40)
  end
  return last
end

local gi = open('pipelines/deferred_gi.lbp')
local pipeline = open('pipelines/deferred.lbp')
local shader = open('shaders/ambient.wgsl')
published_after(pipeline, 0, function(n) return n == 0 end)
published_after(gi, 0, function(n) return n == 0 end)
vim.wait(500)

local out = { pipeline = {}, shader = {} }
local prow, pline = line_of(pipeline, 'reads gbuf.albedo, gbuf.emissive')
local pcol = select(2, string.find(pline, 'gbuf.albedo', 1, true))
local srow, sline = line_of(shader, 'let p = vec2<i32>(pos.xy);')
local scol = #sline
for _ = 1, rounds do
  -- `gbuf.albedo` becomes `gbuf.albedoxy` (an unknown resource), then right again.
  local t = type_at(pipeline, prow, pcol, 'xy')
  table.insert(out.pipeline, published_after(pipeline, t, function(_, m) return m:find('gbuf.albedoxy', 1, true) end))
  vim.wait(200)
  t = type_at(pipeline, prow, pcol, 2)
  table.insert(out.pipeline, published_after(pipeline, t, function(n) return n == 0 end))
  vim.wait(200)
  -- `x` after a statement of the shader (a parse error), then right again.
  t = type_at(shader, srow, scol, 'x')
  table.insert(out.shader, published_after(shader, t, function(n) return n > 0 end))
  vim.wait(200)
  t = type_at(shader, srow, scol, 1)
  table.insert(out.shader, published_after(shader, t, function(n) return n == 0 end))
  vim.wait(200)
end
vim.fn.writefile({ vim.fn.json_encode(out) }, vim.env.LB_OUT)
vim.cmd('qa!')
