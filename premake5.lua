-- Seiche build. Runs under premake5 and, through the shim below, under Debian's premake4.
--   premake5 gmake2   (or: premake4 gmake)   then   make -C build config=release
-- The top-level Makefile drives this; see README.md.

-- premake4 compatibility shim: map the premake5 calls used below onto premake4's API.
local premake4 = _PREMAKE_VERSION and _PREMAKE_VERSION:sub(1, 1) == "4"
if premake4 then
   workspace = solution
   function filter(f)
      if type(f) == "table" then f = f[1] end
      if f == nil or f == "" then return configuration "*" end
      return configuration(f:gsub("^configurations:", ""))
   end
   function symbols(v) if v == "On" then flags { "Symbols" } end end
   function optimize(v) if v ~= "Off" then flags { "OptimizeSpeed" } end end
   function cdialect(v) buildoptions { "-std=" .. v:lower() } end
   function cppdialect(v) buildoptions { "-std=" .. v:lower() } end
   function warnings(v) end
   function externalincludedirs(t) includedirs(t) end
end

local common_warnings = { "-Wall", "-Wextra", "-pedantic" }
local c_warnings = { "-Wmissing-prototypes", "-Wstrict-prototypes" }

workspace "seiche"
   configurations { "release", "debug" }
   location "build"
   targetdir "build/bin"
   objdir "build/obj"
   includedirs { ".", "/usr/include/lua5.4", "/usr/include/bullet", "/usr/include/stb" }
   -- Where the checkout is: tests and the fluid's default shader directory use it.
   -- (premake5 escapes the quotes of a define itself; premake4 passes them to the shell.)
   local source_dir = os.getcwd()
   local q = premake4 and '\\"' or '"'
   defines { "SEICHE_SOURCE_DIR=" .. q .. source_dir .. q,
             "SEICHE_SHADER_DIR=" .. q .. source_dir .. "/shaders" .. q }

   filter "configurations:debug"
      symbols "On"
      optimize "Off"
      defines { "SEICHE_DEBUG=1" }
   filter "configurations:release"
      symbols "On"
      optimize "Speed"
      defines { "NDEBUG" }
   filter {}

local function c_project(name, k)
   project(name)
   kind(k)
   language "C"
   cdialect "C11"
   buildoptions(common_warnings)
   buildoptions(c_warnings)
   buildoptions { "-D_POSIX_C_SOURCE=200809L" }
end

local function cpp_project(name, k)
   project(name)
   kind(k)
   language "C++"
   cppdialect "C++17"
   buildoptions(common_warnings)
end

-- The libraries, bottom up (see docs and ../shared/ARCHITECTURE.md for the rules).
local system_libs = { "imgui", "epoxy", "EGL", "glfw", "lua5.4", "BulletDynamics", "BulletCollision",
                      "LinearMath", "cglm", "stb", "stdc++", "m", "dl", "pthread" }
-- Static libraries are searched in order: each before what it calls (seiche_ui, the ImGui
-- shim, after seiche_engine, which calls it).
local seiche_libs = { "seiche_engine", "seiche_ui", "seiche_coupling", "seiche_phys", "seiche_fluid" }

c_project("seiche_fluid", "StaticLib")
   files { "fluid/*.c", "fluid/*.h", "shaders/fluid/*.h" }

cpp_project("seiche_phys", "StaticLib")
   files { "fluid/bullet/phys*.cpp", "fluid/bullet/phys*.h" }

c_project("seiche_coupling", "StaticLib")
   files { "fluid/bullet/coupling.c", "fluid/bullet/coupling.h" }

c_project("seiche_engine", "StaticLib")
   files { "engine/**.c", "engine/**.h" }

-- The runner's on-screen UI: a C API (engine/app/ui.h) over Dear ImGui (libimgui-dev).
cpp_project("seiche_ui", "StaticLib")
   files { "engine/app/ui_imgui.cpp", "engine/app/ui.h" }
   includedirs { "/usr/include/imgui" }

local function program(name, dir)
   c_project(name, "ConsoleApp")
   files { dir .. "/*.c" }
   links(seiche_libs)
   links(system_libs)
end

program("seiche", "demos/seiche")
program("seiche-bench", "demos/bench")
program("seiche-embed", "demos/embed")

-- One cmocka program per tests/test_*.c.
for _, f in ipairs(os.matchfiles("tests/test_*.c")) do
   local name = path.getbasename(f)
   c_project(name, "ConsoleApp")
   files { f, "tests/support.c", "tests/support.h" }
   links(seiche_libs)
   links { "cmocka" }
   links(system_libs)
end
