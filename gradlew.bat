@rem Gradle launcher for this project, written instead of the usual wrapper jar: it downloads the
@rem distribution named by distributionUrl in gradle\wrapper\gradle-wrapper.properties once into
@rem %USERPROFILE%\.gradle\wrapper\dists (checking distributionSha256Sum when given) and runs it.
@echo off
setlocal
set "DIR=%~dp0"
powershell -NoProfile -ExecutionPolicy Bypass -Command ^
  "$ErrorActionPreference = Stop;" ^
  "$p = @{}; Get-Content %DIR%gradle\wrapper\gradle-wrapper.properties | Where-Object { $_ -match ^[^#].*= } | ForEach-Object { $k, $v = $_ -split =, 2; $p[$k] = $v -replace \\:, : };" ^
  "$url = $p[distributionUrl]; $zip = Split-Path $url -Leaf; $name = $zip -replace \.zip$, ;" ^
  "$gh = if ($env:GRADLE_USER_HOME) { $env:GRADLE_USER_HOME } else { Join-Path $env:USERPROFILE .gradle };" ^
  "$dist = Join-Path $gh (wrapper\dists\ + $name); $gradle = Join-Path $dist (($name -replace -(bin|all)$, ) + \bin\gradle.bat);" ^
  "if (-not (Test-Path $gradle)) { New-Item -ItemType Directory -Force $dist | Out-Null; $tmp = Join-Path $dist ($zip + .part); Write-Host Downloading $url; Invoke-WebRequest -Uri $url -OutFile $tmp;" ^
  "  if ($p[distributionSha256Sum] -and (Get-FileHash $tmp -Algorithm SHA256).Hash -ne $p[distributionSha256Sum].ToUpper()) { Remove-Item $tmp; throw distribution does not match distributionSha256Sum };" ^
  "  Expand-Archive -Force $tmp $dist; Remove-Item $tmp };" ^
  "Set-Content -Path (Join-Path $env:TEMP motion-fusion-gradle.txt) -Value $gradle"
if errorlevel 1 exit /b 1
set /p GRADLE=<"%TEMP%\motion-fusion-gradle.txt"
"%GRADLE%" -p "%DIR%." %*
