// Starts `lightbench lsp` for pipeline files (.lbp, and .ron under the workspace) and the
// shaders they use; everything else is the server's.
const { workspace } = require('vscode');
const { LanguageClient } = require('vscode-languageclient/node');

let client;

exports.activate = function () {
  const command = workspace.getConfiguration('lightbench').get('path', 'lightbench');
  client = new LanguageClient('lightbench', 'lightbench', { command, args: ['lsp'] }, {
    documentSelector: [
      { scheme: 'file', language: 'lbp' },
      { scheme: 'file', pattern: '**/*.ron' },
      { scheme: 'file', pattern: '**/*.{wgsl,frag,vert,comp}' },
    ],
  });
  return client.start();
};

exports.deactivate = function () {
  return client ? client.stop() : undefined;
};
