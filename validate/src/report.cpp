// placeholder until the report writer lands
namespace axg::validate {}
