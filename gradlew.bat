@rem Gradle launcher of this project for Windows, a script in place of the usual wrapper jar: the
@rem PowerShell script gradle\wrapper\gradlew.ps1 downloads and checks the distribution named in
@rem gradle\wrapper\gradle-wrapper.properties (as gradlew does) and prints the path of its gradle.bat,
@rem which then runs here with the arguments given, untouched by PowerShell.
@echo off
setlocal
set "GRADLE_BAT="
for /f "usebackq delims=" %%G in (`powershell.exe -NoProfile -NonInteractive -ExecutionPolicy Bypass -File "%~dp0gradle\wrapper\gradlew.ps1"`) do set "GRADLE_BAT=%%G"
if not defined GRADLE_BAT exit /b 1
call "%GRADLE_BAT%" %*
exit /b %ERRORLEVEL%
