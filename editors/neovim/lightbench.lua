-- Neovim 0.7 or later: `lightbench lsp` for pipeline files (.lbp, .ron) and the shaders
-- they use, one server per project (the folder holding `shaders/`). Put this file in your
-- config (e.g. ~/.config/nvim/plugin/lightbench.lua); `lightbench` must be on PATH.
local function project(file)
  local shaders = vim.fn.finddir('shaders', vim.fn.fnamemodify(file, ':p:h') .. ';')
  if shaders == '' then
    return vim.fn.fnamemodify(file, ':p:h')
  end
  return vim.fn.fnamemodify(shaders, ':p:h:h')
end

local servers = {}
vim.api.nvim_create_autocmd({ 'BufReadPost', 'BufNewFile' }, {
  pattern = { '*.lbp', '*.ron', '*.wgsl', '*.frag', '*.vert', '*.comp' },
  callback = function(args)
    local dir = project(args.file)
    if not servers[dir] then
      servers[dir] = vim.lsp.start_client({
        name = 'lightbench',
        cmd = { 'lightbench', 'lsp' },
        root_dir = dir,
        workspace_folders = { { uri = vim.uri_from_fname(dir), name = dir } },
        -- Every edit at once: the server waits for a pause itself, as long as its checks take.
        flags = { debounce_text_changes = 0 },
      })
    end
    vim.lsp.buf_attach_client(args.buf, servers[dir])
    -- In pipeline files a dotted name (`gbuf.albedo`) is one word: completion replaces it whole.
    if args.file:match('%.lbp$') or args.file:match('%.ron$') then
      vim.bo[args.buf].iskeyword = vim.bo[args.buf].iskeyword .. ',.'
    end
  end,
})
